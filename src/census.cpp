// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform: censusString (pipeline.hpp) of every pixel, coordinates outside the image clamped (replicated
// border).

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

//! Pixel at offset (dx, dy) of the current pixel, through the row pointers and clamped columns of censusRows.
template <typename T>
struct RowWindow
{
    const T* const* rows;   //!< rows y - ry .. y + ry, clamped
    const int* cx;          //!< clamped column index of column x + i, i in [-rx, rx]
    int x;
    T operator()(int dx, int dy) const { return rows[CENSUS_HEIGHT / 2 + dy][cx[x + dx]]; }
};

template <typename T>
static void censusRows(const Mat& img, Mat& census, const Range& rows)
{
    const int W = img.cols, H = img.rows;
    const int rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    // Clamped column indices, so the inner loop has no branches.
    std::vector<int> colIdx(W + 2 * rx);
    for (int i = 0; i < W + 2 * rx; i++)
        colIdx[i] = std::min(std::max(i - rx, 0), W - 1);

    for (int y = rows.start; y < rows.end; y++)
    {
        const T* rowsUp[CENSUS_HEIGHT];
        for (int k = 0; k < CENSUS_HEIGHT; k++)
            rowsUp[k] = img.ptr<T>(std::min(std::max(y + k - ry, 0), H - 1));
        int* dst = census.ptr<int>(y);
        RowWindow<T> at = { rowsUp, colIdx.data() + rx, 0 };
        for (at.x = 0; at.x < W; at.x++)
            dst[at.x] = (int)censusString(at);
    }
}

void censusTransform(const Mat& image, Mat& census)
{
    CV_Assert(image.type() == CV_8UC1 || image.type() == CV_16UC1);
    census.create(image.size(), CV_32SC1);
    parallel_for_(Range(0, image.rows), [&](const Range& r) {
        if (image.depth() == CV_8U)
            censusRows<uchar>(image, census, r);
        else
            censusRows<ushort>(image, census, r);
    }, std::max(1, image.rows / 16));
}

}}} // namespace cv::lidarsgm::detail
