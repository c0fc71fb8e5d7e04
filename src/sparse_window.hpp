// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visiting the sparse disparities inside a square window around each pixel. LiDAR maps are a few percent dense, so
// scanning every window pixel (41 x 41 for the consistency check) would mostly read empty pixels. Instead the sparse
// points are listed per column, sorted by row, and a cursor per column tracks the rows [y - r, y + r] as y advances.

#ifndef OPENCV_LIDARSGM_SPARSE_WINDOW_HPP
#define OPENCV_LIDARSGM_SPARSE_WINDOW_HPP

#include "pipeline.hpp"
#include <algorithm>
#include <vector>

namespace cv { namespace lidarsgm { namespace detail {

struct SparseColumns
{
    std::vector<int> start;    //!< column c's points are [start[c], start[c + 1])
    std::vector<short> row;    //!< their rows, increasing within a column
    std::vector<short> value;  //!< their 1/16-pixel disparities

    explicit SparseColumns(const Mat& sparse16)
    {
        const int W = sparse16.cols, H = sparse16.rows;
        start.assign(W + 1, 0);
        for (int y = 0; y < H; y++)
        {
            const short* s = sparse16.ptr<short>(y);
            for (int x = 0; x < W; x++)
                if (s[x] != NO_DISP)
                    start[x + 1]++;
        }
        for (int x = 0; x < W; x++)
            start[x + 1] += start[x];
        row.resize(start[W]);
        value.resize(start[W]);
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (int y = 0; y < H; y++)
        {
            const short* s = sparse16.ptr<short>(y);
            for (int x = 0; x < W; x++)
                if (s[x] != NO_DISP)
                {
                    row[fill[x]] = (short)y;
                    value[fill[x]++] = s[x];
                }
        }
    }
};

//! Per-thread cursor: for the current row y, [lo[c], hi[c]) are column c's points with rows in [y - r, y + r].
struct WindowCursor
{
    const SparseColumns& cols;
    int radius;
    std::vector<int> lo, hi;

    WindowCursor(const SparseColumns& c, int r, int y0) : cols(c), radius(r)
    {
        const int W = (int)cols.start.size() - 1;
        lo.resize(W);
        hi.resize(W);
        for (int x = 0; x < W; x++)
        {
            const short* b = cols.row.data() + cols.start[x];
            const short* e = cols.row.data() + cols.start[x + 1];
            lo[x] = (int)(std::lower_bound(b, e, y0 - radius) - cols.row.data());
            hi[x] = (int)(std::upper_bound(b, e, y0 + radius) - cols.row.data());
        }
    }

    //! Moves the window to row y (rows only increase).
    void moveTo(int y)
    {
        const int W = (int)lo.size();
        for (int x = 0; x < W; x++)
        {
            const int e = cols.start[x + 1];
            while (lo[x] < e && cols.row[lo[x]] < y - radius)
                lo[x]++;
            while (hi[x] < e && cols.row[hi[x]] <= y + radius)
                hi[x]++;
        }
    }
};

}}} // namespace cv::lidarsgm::detail

#endif
