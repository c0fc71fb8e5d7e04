// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Centre-symmetric census transform, 9x7 window, 31 bits: for each offset o in the first half of the window (rows
// above the centre, then the pixels left of it, in raster order), one bit (I(p + o) > I(p - o)), first offset in the
// most significant of the 31 bits. Coordinates outside the image are clamped (replicated border).

#include "precomp.hpp"
#include "pipeline.hpp"

namespace cv { namespace lidarsgm { namespace detail {

template <typename T>
static void censusRows(const Mat& img, Mat& census, const Range& rows)
{
    const int W = img.cols, H = img.rows;
    const int rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    // Clamped column indices, so the inner loop has no branches.
    std::vector<int> colIdx(W + 2 * rx);
    for (int i = 0; i < W + 2 * rx; i++)
        colIdx[i] = std::min(std::max(i - rx, 0), W - 1);
    const int* cx = colIdx.data() + rx;

    for (int y = rows.start; y < rows.end; y++)
    {
        const T* rowsUp[CENSUS_HEIGHT];
        for (int k = 0; k < CENSUS_HEIGHT; k++)
            rowsUp[k] = img.ptr<T>(std::min(std::max(y + k - ry, 0), H - 1));
        int* dst = census.ptr<int>(y);
        for (int x = 0; x < W; x++)
        {
            unsigned c = 0;
            for (int dy = -ry; dy <= 0; dy++)
            {
                const T* a = rowsUp[ry + dy];
                const T* b = rowsUp[ry - dy];
                const int dxEnd = dy < 0 ? rx : -1;
                for (int dx = -rx; dx <= dxEnd; dx++)
                    c = (c << 1) | (a[cx[x + dx]] > b[cx[x - dx]] ? 1u : 0u);
            }
            dst[x] = (int)c;
        }
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
