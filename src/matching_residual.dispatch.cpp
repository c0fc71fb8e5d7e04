// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// matchingResidual (calibration.hpp): each sparse value against the disparity at which its pixel's census block
// matches the right image best nearby; the per-frame calibration check, cheap beside a fusion call.

#include "precomp.hpp"
#include "projection.hpp"
#include "matching_residual.simd.hpp"
#include "matching_residual.simd_declarations.hpp"
#include <algorithm>
#include <climits>
#include <cmath>

namespace cv { namespace lidarsgm {

namespace detail {

static void runMatchingOffsets(const Mat& censusL, const Mat& censusR, const Point3i* points, int n, Point move,
                               const Range& rows, int radius, int uniqueness1024, std::vector<int>& offsets16)
{
    CV_CPU_DISPATCH(matchingOffsets, (censusL, censusR, points, n, move, rows, radius, uniqueness1024, offsets16),
                    CV_CPU_DISPATCH_MODES_ALL);
}

} // namespace detail

namespace {

/** The sparse values of a pair, each point (x, y, value in 1/16 pixel) in the coordinates of the census strings of
rows [y0, y0 + census rows): those rows alone, the points' rows and `reach` more on each side (a scan covers part of
the image: on KITTI the lower two thirds). A string within the band's inner rows is the full image's, its 9x7 window
lying inside the band or clamped at the image's own border. */
struct SparsePoints
{
    std::vector<Point3i> points;
    Mat censusL, censusR;
    int y0 = 0;
    Range rows;   //!< the band rows a 3x3 block may sit on: not the image's first and last

    SparsePoints(const Mat& l, const Mat& r, const Mat& sparse16, int reach)
    {
        // In bands of rows at once, each band's points then appended in turn: row-major order, as the medians'
        // subsets (every k-th point) take them.
        const int H = sparse16.rows, bands = std::max(1, std::min(16, (H - 2) / 16));
        std::vector<std::vector<Point3i> > found(bands);
        parallel_for_(Range(0, bands), [&](const Range& range) {
            for (int b = range.start; b < range.end; b++)
                for (int y = 1 + (H - 2) * b / bands; y < 1 + (H - 2) * (b + 1) / bands; y++)
                {
                    const short* s = sparse16.ptr<short>(y);
                    for (int x = 0; x < sparse16.cols; x++)
                        if (s[x] != detail::NO_DISP)
                            found[b].push_back(Point3i(x, y, s[x]));
                }
        });
        for (const std::vector<Point3i>& f : found)
            points.insert(points.end(), f.begin(), f.end());
        if (points.empty())
            return;
        const int ry = detail::CENSUS_HEIGHT / 2;
        y0 = std::max(points.front().y - reach - 1 - ry, 0);
        const int y1 = std::min(points.back().y + reach + 2 + ry, H);
        detail::censusTransform(l.rowRange(y0, y1), censusL);
        detail::censusTransform(r.rowRange(y0, y1), censusR);
        for (Point3i& p : points)
            p.y -= y0;
        rows = Range(std::max(1 - y0, 1), std::min(H - 1 - y0, censusL.rows - 1));
    }

    /** The median |value - matched| (1/16 pixel) over pts (points or a subset of them) moved by `move` that have a
    unique match, or -1 where fewer than kMinCalibrationPoints have one (count receives how many do). */
    int medianOffset16(const std::vector<Point3i>& pts, Point move, int radius, int& count) const
    {
        // The matcher's default uniqueness ratio, as the pipeline takes it (x 1024, rounded).
        static const int uniqueness1024 = cvRound(StereoLidarSGM::create()->getUniquenessRatio() * 1024);
        // In chunks, so that they run in parallel.
        const int n = (int)pts.size(), chunk = 1024, chunks = (n + chunk - 1) / chunk;
        std::vector<std::vector<int> > offsets(chunks);
        parallel_for_(Range(0, chunks), [&](const Range& range) {
            for (int c = range.start; c < range.end; c++)
                detail::runMatchingOffsets(censusL, censusR, pts.data() + c * chunk, std::min(chunk, n - c * chunk),
                                           move, rows, radius, uniqueness1024, offsets[c]);
        });
        std::vector<int> all;
        for (const std::vector<int>& v : offsets)
            all.insert(all.end(), v.begin(), v.end());
        count = (int)all.size();
        if (count < detail::kMinCalibrationPoints)
            return -1;
        std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
        return all[all.size() / 2];
    }
};

//! pts (in the band's coordinates: rows from y0) turned by deg about the centre of an image of `size` (checkLidar).
std::vector<Point3i> turned(const std::vector<Point3i>& pts, double deg, Size size, int y0)
{
    const double a = deg * CV_PI / 180, c = std::cos(a), s = std::sin(a);
    const double cx = (size.width - 1) * 0.5, cy = (size.height - 1) * 0.5;
    std::vector<Point3i> out(pts.size());
    for (size_t i = 0; i < pts.size(); i++)
    {
        const double x = pts[i].x - cx, y = pts[i].y + y0 - cy;
        out[i] = Point3i(cvRound(cx + c * x - s * y), cvRound(cy + s * x + c * y) - y0, pts[i].z);
    }
    return out;
}

//! The inputs of matchingResidual and checkLidar checked, and the sparse map in 1/16 pixel.
void residualInputs(InputArray left, InputArray right, InputArray sparseDisparity, const char* fn, Mat& l, Mat& r,
                    Mat& sparse16)
{
    if (left.kind() == _InputArray::CUDA_GPU_MAT || right.kind() == _InputArray::CUDA_GPU_MAT ||
        sparseDisparity.kind() == _InputArray::CUDA_GPU_MAT)
        LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm: %s runs on the CPU: pass cv::Mat inputs", fn));
    detail::checkInputs(left, right, sparseDisparity, noArray(), true, fn);
    l = left.getMat();
    r = right.getMat();
    detail::convertSparse(sparseDisparity.getMat(), 0, l.cols, sparse16);
}

} // namespace

double matchingResidual(InputArray left, InputArray right, InputArray sparseDisparity, int searchRadius)
{
    CV_INSTRUMENT_REGION();
    Mat l, r, sparse16;
    residualInputs(left, right, sparseDisparity, "matchingResidual", l, r, sparse16);
    LIDARSGM_Check(searchRadius >= 1 && searchRadius <= 64,
                   "lidarsgm: matchingResidual: searchRadius must be in [1, 64]");
    const SparsePoints sp(l, r, sparse16, 0);
    int count = 0;
    const int median16 = sp.medianOffset16(sp.points, Point(), searchRadius, count);
    if (median16 < 0)
        LIDARSGM_Error_(Error::StsError, ("lidarsgm: matchingResidual: only %d sparse pixels can be compared with the images "
                                          "(at least %d needed): textureless images, an empty sparse map, or one outside "
                                          "the images' overlap", count, detail::kMinCalibrationPoints));
    return median16 / 16.0;
}

LidarCheck checkLidar(InputArray left, InputArray right, InputArray sparseDisparity, double maxResidual, int maxShift)
{
    CV_INSTRUMENT_REGION();
    Mat l, r, sparse16;
    residualInputs(left, right, sparseDisparity, "checkLidar", l, r, sparse16);
    if (maxResidual == 0)
        maxResidual = LidarFailSafe::maxResidual();
    LIDARSGM_Check(maxResidual > 0 && maxResidual < 64,
                   "lidarsgm: checkLidar: maxResidual must be in (0, 64) pixels (0: LidarFailSafe::maxResidual())");
    LIDARSGM_Check(maxShift >= 0 && maxShift <= 1024, "lidarsgm: checkLidar: maxShift must be in [0, 1024] pixels");
    if (maxShift == 0)
        maxShift = std::max(l.cols / detail::kLidarShiftFraction, 1);
    const int radius = 6;   // matchingResidual's default
    LidarCheck c;
    // The band reaches the moves and the turns.
    const int turnReach = cvCeil(l.cols * 0.5 * std::sin(detail::kLidarMaxTurn * CV_PI / 180));
    const SparsePoints sp(l, r, sparse16, maxShift + turnReach);
    int count = 0;
    const int at0 = sp.medianOffset16(sp.points, Point(), radius, count);
    if (at0 < 0)
        return c;   // the images cannot tell: residual NaN, trusted
    c.residual = c.shiftedResidual = at0 / 16.0;
    if (c.residual <= maxResidual)
        return c;
    // Above the band: is the map right but misplaced (a calibration error moves the points on the image), or do the
    // images match poorly? Search the moves of the map, coarse to fine, for the one with the lowest residual, on
    // every step-th point (the median of a few thousand is as good, at a fraction of the cost), taken once.
    const size_t step = std::max<size_t>(1, sp.points.size() / detail::kLidarSearchPoints);
    std::vector<Point3i> taken;
    for (size_t i = 0; i < sp.points.size(); i += step)
        taken.push_back(sp.points[i]);
    int best = step > 1 ? sp.medianOffset16(taken, Point(), radius, count) : at0;
    if (best < 0)
        return c;
    const int start = best;
    // The median of pts moved by (dx, dy), clamped to the search's reach, where it is lower than *low.
    const auto tryMove = [&](const std::vector<Point3i>& pts, int dx, int dy, int* low, Point* at) {
        const Point move(std::max(-maxShift, std::min(maxShift, dx)), std::max(-maxShift, std::min(maxShift, dy)));
        const int m = sp.medianOffset16(pts, move, radius, count);
        if (m >= 0 && m < *low)
        {
            *low = m;
            *at = move;
        }
    };
    // The eight moves of pts around the best one, g pixels apart.
    const auto tryAround = [&](const std::vector<Point3i>& pts, int g) {
        const Point centre = c.shift;
        for (int j = -1; j <= 1; j++)
            for (int i = -1; i <= 1; i++)
                if (i != 0 || j != 0)
                    tryMove(pts, centre.x + i * g, centre.y + j * g, &best, &c.shift);
    };
    int grid = (maxShift + 3) / 4;
    for (int j = -4; j <= 4; j++)
        for (int i = -4; i <= 4; i++)
            if (i != 0 || j != 0)
                tryMove(taken, i * grid, j * grid, &best, &c.shift);
    while (grid > 1)
    {
        grid = (grid + 1) / 2;
        tryAround(taken, grid);
    }
    c.shiftedResidual = best / 16.0;
    c.trusted = !(best < detail::kLidarShiftGain * start);
    if (!c.trusted)
        return c;
    // No move condemns the map: turns of it (a rolled LiDAR). Half degrees (half a degree moves KITTI's image edges
    // by 5 pixels, beyond which a block's match is lost), each unmoved and at the best move (which may have made up
    // for part of the turn), the move refined around the best turn (steps of 4, 2 and 1 pixels), then quarter
    // degrees beside it, and the move refined again: about 80 evaluations.
    std::vector<Point3i> bestTurned;   // taken turned by c.turn
    const Point moved = c.shift;
    const auto tryTurn = [&](double deg) {
        if (deg == 0 || std::abs(deg) > detail::kLidarMaxTurn)
            return;
        std::vector<Point3i> pts = turned(taken, deg, l.size(), sp.y0);
        int low = best;
        Point at = c.shift;
        tryMove(pts, 0, 0, &low, &at);
        if (moved != Point())
            tryMove(pts, moved.x, moved.y, &low, &at);
        if (low < best)
        {
            best = low;
            c.turn = deg;
            c.shift = at;
            bestTurned.swap(pts);
        }
    };
    const auto refineMove = [&]() {
        for (int g = 4; c.turn != 0 && g >= 1; g /= 2)
            tryAround(bestTurned, g);
    };
    for (double deg = 0.5; deg <= detail::kLidarMaxTurn; deg += 0.5)
    {
        tryTurn(-deg);
        tryTurn(deg);
    }
    refineMove();
    const double coarse = c.turn;
    tryTurn(coarse - 0.25);
    tryTurn(coarse + 0.25);
    if (c.turn != coarse)
        refineMove();
    c.shiftedResidual = best / 16.0;
    c.trusted = !(best < detail::kLidarShiftGain * start);
    return c;
}

}} // namespace cv::lidarsgm
