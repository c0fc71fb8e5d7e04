// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The legends below the colour pictures (opencv2/lidarsgm/evaluation.hpp): the tool and the Python samples draw them
// with these, so a picture reads the same from every front end.

#include "../precomp.hpp"
#include "opencv2/lidarsgm/evaluation.hpp"
#include "error_bands.hpp"
#include "opencv2/imgproc.hpp"

namespace cv { namespace lidarsgm {

namespace {

// ---- the legends below the pictures ------------------------------------------------------------------------------
// A white band under the frame: the frame's rows stay as the library drew them, the band explains their colours with
// the same library functions (colorizeDisparity, colorizeDisparityError), so that the legend cannot drift from them.

const int kFont = FONT_HERSHEY_SIMPLEX;

//! The legend's text size: 0.7 at KITTI's 1242 columns (its half-size copies in doc/ stay readable), with the width.
double legendScale(int width)
{
    return std::min(1.8, std::max(0.35, 0.7 * width / 1242.0));
}

//! The largest scale up to `scale` at which text fits in `width` pixels.
double fitScale(const std::string& text, double scale, int width)
{
    const int w = getTextSize(text, kFont, scale, 1, nullptr).width;
    return w <= width ? scale : scale * width / w;
}

struct Band
{
    Mat all, band;        //!< the picture with its band; the band alone
    double scale;
    int text, pad;        //!< the height of a line of text, the margin
};

//! picture (CV_8UC3) over a white band for `lines` lines of text (1.6 text heights each) and its margins.
Band addBand(const Mat& picture, double lines)
{
    Band b;
    b.scale = legendScale(picture.cols);
    b.text = getTextSize("0", kFont, b.scale, 1, nullptr).height;
    b.pad = std::max(3, b.text / 2);
    const int h = cvRound(lines * b.text * 1.6) + 2 * b.pad;
    b.all.create(picture.rows + h, picture.cols, CV_8UC3);
    picture.copyTo(b.all.rowRange(0, picture.rows));
    b.band = b.all.rowRange(picture.rows, b.all.rows);
    b.band.setTo(Scalar::all(255));
    return b;
}

void text(Mat& img, const std::string& t, Point at, double scale, const Scalar& colour = Scalar::all(0))
{
    putText(img, t, at, kFont, scale, colour, 1, LINE_AA);
}

Mat checkedPicture(InputArray picture)
{
    LIDARSGM_Check(picture.type() == CV_8UC3 && !picture.empty(),
                   "lidarsgm: a legend goes below a CV_8UC3 picture (colorizeDisparity, colorizeDisparityError, "
                   "drawSparseDisparity)");
    return picture.getMat();
}

} // namespace

void addDisparityLegend(InputArray _picture, OutputArray withLegend, double maxDisparity, const String& title,
                        bool none)
{
    const Mat picture = checkedPicture(_picture);
    LIDARSGM_Check(maxDisparity > 0, "lidarsgm: addDisparityLegend: maxDisparity must be > 0");
    Band b = addBand(picture, 2.2);
    const int pad = b.pad, W = picture.cols;
    // Row 1: the title, the colour bar, a black swatch for "none"; row 2: the ticks' disparities under the bar.
    const double titleScale = fitScale(title, b.scale, W / 4);
    const int titleW = getTextSize(title, kFont, titleScale, 1, nullptr).width;
    const int barH = b.text + b.pad / 2, y0 = pad, x0 = pad + titleW + 2 * pad;
    // The largest disparity's label is centred on the bar's end: room for its half on the right.
    const int labelW = getTextSize(format("%d", cvRound(maxDisparity)), kFont, b.scale, 1, nullptr).width;
    const int noneW = none ? barH + pad / 2 + getTextSize("none", kFont, b.scale, 1, nullptr).width + 2 * pad : 0;
    const int x1 = W - pad - std::max(noneW, labelW / 2), barW = x1 - x0;
    text(b.band, title, Point(pad, y0 + (barH + b.text) / 2), titleScale);
    if (barW < 16)
    {
        b.all.copyTo(withLegend);
        return;
    }
    Mat ramp(1, barW, CV_32F), colours;
    for (int x = 0; x < barW; x++)
        ramp.at<float>(x) = (float)(maxDisparity * x / (barW - 1));
    colorizeDisparity(ramp, colours, maxDisparity);
    repeat(colours, barH, 1, b.band(Rect(x0, y0, barW, barH)));
    rectangle(b.band, Rect(x0 - 1, y0 - 1, barW + 2, barH + 2), Scalar::all(128));
    if (none)
    {
        const Rect swatch(x1 + 2 * pad, y0, barH, barH);
        b.band(swatch).setTo(Scalar::all(0));
        rectangle(b.band, Rect(swatch.x - 1, y0 - 1, barH + 2, barH + 2), Scalar::all(128));
        text(b.band, "none", Point(swatch.x + barH + pad / 2, y0 + (barH + b.text) / 2), b.scale);
    }
    // Ticks every 1, 2 or 5 x 10^k px, as many as their labels leave room for, and always the largest disparity (a
    // regular tick too close to it left out).
    const double room = (double)barW / (labelW + b.text);
    double step = 1;
    for (double k = 1; maxDisparity / step > room; k *= 10)
        for (double m : { 1.0, 2.0, 5.0 })
            if (maxDisparity / step > room)
                step = m * k;
    const auto tick = [&](double d) {
        const int x = x0 + cvRound(d / maxDisparity * (barW - 1));
        line(b.band, Point(x, y0 + barH), Point(x, y0 + barH + b.pad / 2 + 1), Scalar::all(0));
        const std::string l = format("%g", d);
        const int w = getTextSize(l, kFont, b.scale, 1, nullptr).width;
        text(b.band, l, Point(x - w / 2, y0 + barH + b.pad / 2 + 2 + b.text + b.pad / 2), b.scale);
    };
    for (double d = 0; (maxDisparity - d) / maxDisparity * barW > labelW + b.text / 2; d += step)
        tick(d);
    tick(maxDisparity);
    b.all.copyTo(withLegend);
}

void addErrorLegend(InputArray _picture, OutputArray withLegend)
{
    const Mat picture = checkedPicture(_picture);
    Band b = addBand(picture, 2.4);
    const int pad = b.pad, W = picture.cols;
    // The bands of colorizeDisparityError (error_bands.hpp): the error over the D1 threshold, max(3 px, 5 % of the
    // true disparity), labelled by their edges ("1/16 - 1/8"), the first and the last by their one edge.
    const int n = (int)(sizeof(detail::ERROR_BANDS) / sizeof(detail::ERROR_BANDS[0]));
    const auto edge = [](float e) { return e < 1 ? format("1/%d", cvRound(1 / e)) : format("%g", e); };
    std::vector<std::string> labels;
    for (int k = 0; k < n; k++)
    {
        const detail::ErrorBand& band = detail::ERROR_BANDS[k];
        labels.push_back(k == 0 ? "< " + edge(band.hi) : k == n - 1 ? ">= " + edge(band.lo)
                                                                    : edge(band.lo) + " - " + edge(band.hi));
    }
    const std::string title = "error / max(3 px, 5 % of the true disparity), the D1 threshold: 1 and above are D1 "
                              "outliers; black: no ground truth";
    const double titleScale = fitScale(title, b.scale, W - 2 * pad);
    text(b.band, title, Point(pad, pad + b.text), titleScale);
    const int y0 = pad + b.text + b.pad, h = b.band.rows - y0 - pad, cellW = (W - 2 * pad) / n;
    double labelScale = b.scale;
    for (const std::string& l : labels)
        labelScale = std::min(labelScale, fitScale(l, b.scale, cellW - 2 * pad));
    for (int k = 0; k < n; k++)
    {
        const Rect cell(pad + k * cellW, y0, cellW, h);
        const detail::ErrorBand& band = detail::ERROR_BANDS[k];
        const Vec3b c(band.b, band.g, band.r);
        b.band(cell).setTo(Scalar(c[0], c[1], c[2]));
        const bool dark = 0.114 * c[0] + 0.587 * c[1] + 0.299 * c[2] < 128;
        const Size ts = getTextSize(labels[k], kFont, labelScale, 1, nullptr);
        text(b.band, labels[k], Point(cell.x + (cellW - ts.width) / 2, y0 + (h + ts.height) / 2), labelScale,
             dark ? Scalar::all(255) : Scalar::all(0));
    }
    b.all.copyTo(withLegend);
}

}} // namespace cv::lidarsgm
