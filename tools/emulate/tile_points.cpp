// SIMT emulation (simt.hpp), on the CPU, of the tiles' sparse point lists (listSparseRowsKernel, src_cuda/sparse_input.cu,
// then listTilePoints, src_cuda/sparse_window.cuh) in two versions of those files (tools/emulate_kernel.sh extracts
// them into old.inc and new.inc): both list the same random sparse map (values of either sign, a random density, up
// to the image's edges) for every block of 32 x 8 or 32 x 16 pixels and a random radius, and each block's list (its
// points in order, the rows' starts, the tile's first row and row count, the largest value) is compared with the
// other version's and with a direct listing of the tile's pixels.
#include "simt.hpp"
#include "cases.hpp"
#include "cuda_stages.hpp"
#include "histogram.cuh"

#include "versions.hpp"

namespace {

//! One block (bx, by) of bw x bh threads calling list(smem); returns what thread 0 got (a version's TilePoints).
template <class List> auto runBlock(int bx, int by, int bw, int bh, std::vector<int>& smem, List list)
{
    decltype(list(smem.data())) got{};
    gridDim = dim3(bx + 1, by + 1);
    std::barrier<> bb(bw * bh);
    blockBar = &bb;
    std::vector<WarpSync> ws(bw * bh / 32);
    std::vector<std::thread> th;
    for (int t = 0; t < bw * bh; t++)
        th.emplace_back([&, t]() {
            threadIdx = make_uint3(t % bw, t / bw, 0); blockIdx = make_uint3(bx, by, 0); blockDim = dim3(bw, bh);
            tw = &ws[t / 32]; tlane = t % 32;
            const auto tp = list(smem.data());
            if (t == 0) got = tp;
        });
    for (auto& x : th) x.join();
    return got;
}

} // namespace

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int W = U(1, 200), H = U(1, 90), density = U(0, 60), r = U(0, 30), bw = 32, bh = 8 * U(1, 2);
    std::vector<short> map((size_t)W * H, NO_DISP);
    for (auto& v : map)
        if (U(1, 100) <= density) v = (short)U(-300, 2047);
    cv::cuda::PtrStepSz<short> sparse(H, W, map.data(), W * sizeof(short));
    const int C = W / 32 + 1;
    std::vector<int2> chunks[2];
    std::vector<int> entries[2];
    SparseRows rows[2];
    for (int v = 0; v < 2; v++)
    {
        chunks[v].assign((size_t)H * C, make_int2(-7, -7));
        entries[v].assign((size_t)W * H, -9);
        rows[v] = { cv::cuda::PtrStepSz<int2>(H, C, chunks[v].data(), C * sizeof(int2)),
                    cv::cuda::PtrStepSz<int>(H, W, entries[v].data(), W * sizeof(int)) };
        const dim3 grid((H + 7) / 8);
        if (v == 0)
            launch(grid, dim3(32, 8), [&]() { oldv::listSparseRowsKernel(sparse, rows[0]); });
        else
            launch(grid, dim3(32, 8), [&]() { newv::listSparseRowsKernel(sparse, rows[1]); });
    }
    std::vector<int> smem[2] = { std::vector<int>(oldv::tilePointsBytes(bw, bh, r) / sizeof(int) + 2),
                                 std::vector<int>(newv::tilePointsBytes(bw, bh, r) / sizeof(int) + 2) };
    int differ = 0, wrong = 0, blocks = 0, points = 0;
    for (int by = 0; by < (H + bh - 1) / bh; by++)
        for (int bx = 0; bx < (W + bw - 1) / bw; bx++)
        {
            const auto a = runBlock(bx, by, bw, bh, smem[0],
                                          [&](int* s) { return oldv::listTilePoints(rows[0], r, s); });
            const auto b = runBlock(bx, by, bw, bh, smem[1],
                                          [&](int* s) { return newv::listTilePoints(rows[1], r, s); });
            // The tile's pixels, row by row and left to right.
            const int x0 = std::max(bx * bw - r, 0), x1 = std::min(bx * bw + bw + r, W);
            const int y0 = std::max(by * bh - r, 0), y1 = std::min(by * bh + bh + r, H);
            std::vector<int> list, starts;
            int top = INT_MIN;
            for (int y = y0; y < y1; y++)
            {
                starts.push_back((int)list.size() / 2);
                for (int x = x0; x < x1; x++)
                    if (map[(size_t)y * W + x] != NO_DISP)
                    {
                        list.push_back(y << 16 | x);
                        list.push_back(map[(size_t)y * W + x]);
                        top = std::max(top, (int)map[(size_t)y * W + x]);
                    }
            }
            starts.push_back((int)list.size() / 2);
            const auto same = [&](const auto& t) {
                bool ok = t.y0 == y0 && t.rows == y1 - y0 && t.maxValue == top;
                for (size_t i = 0; ok && i < list.size(); i++) ok = t.points[i] == list[i];
                for (size_t i = 0; ok && i < starts.size(); i++) ok = t.rowStart[i] == starts[i];
                return ok;
            };
            const bool sa = same(a), sb = same(b);
            wrong += !sb;
            differ += sa != sb;
            blocks++;
            points += (int)list.size() / 2;
        }
    printf("seed %d: %dx%d r %d, blocks of 32 x %d: %d blocks, %d points listed, %d blocks against the direct listing, "
           "%d differ\n", U.seed, W, H, r, bh, blocks, points, wrong, differ + wrong);
    return differ + wrong != 0;
}
