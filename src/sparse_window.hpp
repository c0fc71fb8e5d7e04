// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visiting the sparse disparities inside a square window around each pixel. LiDAR maps are a few percent dense, so
// scanning every window pixel (41 x 41 for the consistency check) would mostly read empty pixels. Instead the sparse
// points are listed per column, sorted by row, and a cursor per column tracks the rows [y - r, y + r] as y advances:
// from one row to the next only the points of the row entering the window and of the row leaving it move a cursor.

#ifndef OPENCV_LIDARSGM_SPARSE_WINDOW_HPP
#define OPENCV_LIDARSGM_SPARSE_WINDOW_HPP

#include "pipeline.hpp"
#include <algorithm>
#include <cstring>
#include <vector>

namespace cv { namespace lidarsgm { namespace detail {

struct SparseColumns
{
    std::vector<int> start;    //!< column c's points are [start[c], start[c + 1])
    std::vector<short> row;    //!< their rows, increasing within a column
    std::vector<short> value;  //!< their 1/16-pixel disparities
    std::vector<int> rowStart; //!< row y's points are byRow[rowStart[y] .. rowStart[y + 1]), left to right
    std::vector<int> byRow;    //!< a point's index in row / value
    std::vector<short> column; //!< the column of byRow's points (row-major order)
    std::vector<short> rowValue; //!< the value of byRow's points (row-major order)

    SparseColumns() {}
    explicit SparseColumns(const Mat& sparse16) { build(sparse16); }

    //! Lists the points of a CV_16SC1 map (NO_DISP: none); an empty map gives none.
    void build(const Mat& sparse16)
    {
        const int W = sparse16.cols, H = sparse16.rows;
        start.assign(W + 1, 0);
        rowStart.assign(H + 1, 0);
        column.clear();
        rowValue.clear();
        std::vector<short>& values = rowValue;
        // Row by row, skipping four empty pixels at a time (NO_DISP is 0x8000).
        const uint64 empty4 = 0x8000800080008000ull;
        for (int y = 0; y < H; y++)
        {
            const short* s = sparse16.ptr<short>(y);
            int x = 0;
            for (; x + 4 <= W; x += 4)
            {
                uint64 q;
                memcpy(&q, s + x, sizeof(q));
                if (q == empty4)
                    continue;
                for (int k = x; k < x + 4; k++)
                    if (s[k] != NO_DISP)
                    {
                        column.push_back((short)k);
                        values.push_back(s[k]);
                    }
            }
            for (; x < W; x++)
                if (s[x] != NO_DISP)
                {
                    column.push_back((short)x);
                    values.push_back(s[x]);
                }
            rowStart[y + 1] = (int)column.size();
        }
        // Counting sort by column: rows stay increasing within a column.
        const int n = (int)column.size();
        for (int i = 0; i < n; i++)
            start[column[i] + 1]++;
        for (int x = 0; x < W; x++)
            start[x + 1] += start[x];
        row.resize(n);
        value.resize(n);
        byRow.resize(n);
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (int y = 0; y < H; y++)
            for (int i = rowStart[y]; i < rowStart[y + 1]; i++)
            {
                const int j = fill[column[i]]++;
                row[j] = (short)y;
                value[j] = values[i];
                byRow[i] = j;
            }
    }
};

//! Per-thread cursor: for the current row y, [lo[c], hi[c]) are column c's points with rows in [y - r, y + r].
struct WindowCursor
{
    const SparseColumns& cols;
    int radius, y;
    std::vector<int> lo, hi;

    WindowCursor(const SparseColumns& c, int r, int y0) : cols(c), radius(r), y(y0)
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

    //! Moves the window to row y (rows only increase): each point of the rows entering it moves its column's hi
    //! past it, each point of the rows leaving it its column's lo (within a column the points are in row order).
    void moveTo(int yNew)
    {
        const int H = (int)cols.rowStart.size() - 1;
        for (; y < yNew; y++)
        {
            const int enter = y + 1 + radius, leave = y - radius;
            if (enter < H)
                for (int i = cols.rowStart[enter]; i < cols.rowStart[enter + 1]; i++)
                    hi[cols.column[i]]++;
            if (leave >= 0)
                for (int i = cols.rowStart[leave]; i < cols.rowStart[leave + 1]; i++)
                    lo[cols.column[i]]++;
        }
    }
};

}}} // namespace cv::lidarsgm::detail

#endif
