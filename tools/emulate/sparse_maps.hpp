// What the emulated cases of the stages that read the sparse map share (tools/emulate/*.cpp; after versions.hpp):
// its rows listed as listSparseRowsKernel lists them, and each column's nearest points above and below, as
// ringNeighboursKernel finds them.
#ifndef LIDARSGM_TOOLS_EMULATE_SPARSE_MAPS_HPP
#define LIDARSGM_TOOLS_EMULATE_SPARSE_MAPS_HPP
#include <vector>

//! SparseRows of a W x H map: a chunk's points before it in its row and its bits, each point at its rank in the row.
struct ListedRows
{
    std::vector<int2> chunks;
    std::vector<int> entries;
    SparseRows rows;
    ListedRows(const std::vector<short>& map, int W, int H) : chunks((size_t)H * (W / 32 + 1)), entries((size_t)W * H, -9)
    {
        const int C = W / 32 + 1;
        for (int y = 0; y < H; y++)
        {
            int n = 0;
            for (int c = 0; c < C; c++)
            {
                unsigned bits = 0;
                for (int b = 0; b < 32 && 32 * c + b < W; b++)
                    if (map[(size_t)y * W + 32 * c + b] != NO_DISP)
                        bits |= 1u << b;
                chunks[(size_t)y * C + c] = make_int2(n, (int)bits);
                for (int b = 0; b < 32; b++)
                    if (bits >> b & 1u)
                        entries[(size_t)y * W + n++] = (int)((unsigned)map[(size_t)y * W + 32 * c + b] << 16) | (32 * c + b);
            }
        }
        rows = { cv::cuda::PtrStepSz<int2>(H, C, chunks.data(), C * sizeof(int2)),
                 cv::cuda::PtrStepSz<int>(H, W, entries.data(), W * sizeof(int)) };
    }
};

//! Each column's nearest points strictly above and below each pixel (their rows, -1: none) of a W x H map.
struct RingNeighbours
{
    std::vector<short> above, below;
    RingNeighbours(const std::vector<short>& map, int W, int H) : above((size_t)W * H), below((size_t)W * H)
    {
        for (int x = 0; x < W; x++)
        {
            short a = -1, b = -1;
            for (int y = 0; y < H; y++)
            {
                above[(size_t)y * W + x] = a;
                if (map[(size_t)y * W + x] != NO_DISP)
                    a = (short)y;
            }
            for (int y = H - 1; y >= 0; y--)
            {
                below[(size_t)y * W + x] = b;
                if (map[(size_t)y * W + x] != NO_DISP)
                    b = (short)y;
            }
        }
    }
};

#endif
