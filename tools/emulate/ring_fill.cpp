// SIMT emulation (simt.hpp), on the CPU, of ring interpolation's fill (ringFillKernel, src_cuda/ring_interpolation.cu)
// in two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and new.inc): both take the same
// random case (scan lines with gaps or scattered points, values in and out of the range, a semidense map partly
// filled, census strings of few bits so that the census test both passes and fails, a random gap limit), each with
// its own launch shape, and their maps are compared pixel for pixel, and with the CPU's rule (ringCandidate16,
// sparseInRange and the census test of pipeline.hpp, pixel by pixel).
#include "simt.hpp"
#include "cases.hpp"
#include "cuda_stages.hpp"
#include "pixel_rows.cuh"

#include "versions.hpp"
#include "sparse_maps.hpp"

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int seed = U.seed;
    const int W = U(1, 150), H = U(1, 110), lo = U(0, 3) == 0 ? U(1, 8) : 0, hi = lo + U(8, 80);
    const bool lines = U(0, 1);
    const int lineStep = U(1, 12), density = U(1, 100), filled = U(0, 100), Ts = U(1, 5);
    const int gap = U(0, 3) == 0 ? U(0, 3) : U(1, 40);
    std::vector<short> sparse((size_t)W * H, NO_DISP);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if ((!lines || y % lineStep == 0) && U(1, 100) <= density)
                sparse[(size_t)y * W + x] = (short)U(16 * (lo > 2 ? lo - 2 : 0), 16 * (hi + 2));
    RingNeighbours nb(sparse, W, H);
    std::vector<short>&above = nb.above, &below = nb.below;
    std::vector<int> cl((size_t)W * H), cr((size_t)W * H);
    for (auto& v : cl) v = 1 << U(0, 4) | 1 << U(0, 4);
    for (auto& v : cr) v = 1 << U(0, 4) | 1 << U(0, 4);
    std::vector<short> start((size_t)W * H, NO_DISP);
    for (auto& v : start)
        if (U(1, 100) <= filled)
            v = (short)U(0, 16 * hi);
    std::vector<int> stats(RING_GAP_BINS + 1, 0);
    stats[RING_GAP_BINS] = gap;
    using cv::cuda::PtrStepSz;
    const PtrStepSz<int> censusL(H, W, cl.data(), W * sizeof(int)), censusR(H, W, cr.data(), W * sizeof(int));
    const PtrStepSz<short> sp(H, W, sparse.data(), W * sizeof(short)), ab(H, W, above.data(), W * sizeof(short)),
        be(H, W, below.data(), W * sizeof(short));
    std::vector<short> out[2] = { start, start };
    for (int v = 0; v < 2; v++)
    {
        const PtrStepSz<short> o(H, W, out[v].data(), W * sizeof(short));
        const bool rows = v == 0 ? oldv::RING_FILL_PIXEL_ROWS : newv::RING_FILL_PIXEL_ROWS;
        const dim3 grid = rows ? PixelRows::grid(W, H) : dim3((W + 31) / 32, (H + 7) / 8);
        const dim3 block = rows ? PixelRows::block() : dim3(32, 8);
        if (v == 0)
            launch(grid, block, [&]() { oldv::ringFillKernel(censusL, censusR, sp, ab, be, stats.data(), Ts, lo, hi, o); });
        else
            launch(grid, block, [&]() { newv::ringFillKernel(censusL, censusR, sp, ab, be, stats.data(), Ts, lo, hi, o); });
    }
    int diff = 0, wrong = 0, fills = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
        {
            const size_t i = (size_t)y * W + x;
            int want = start[i];
            if (want == NO_DISP)
            {
                const int c = ringCandidate16(above.data(), below.data(), W, sparse.data(), W, x, y, W, gap);
                if (c != NO_DISP && sparseInRange(c, lo, hi))
                {
                    const int xr = std::min(std::max(x - roundDisp16(c), 0), W - 1);
                    if (popcount32((unsigned)cl[i] ^ (unsigned)cr[(size_t)y * W + xr]) < Ts)
                        want = c;
                }
                fills += want != NO_DISP;
            }
            diff += out[0][i] != out[1][i];
            wrong += out[1][i] != want;
        }
    printf("seed %d: %dx%d %s, %d filled, %d pixels against the CPU's rule, %d differ\n", seed, W, H,
           lines ? "lines" : "scattered", fills, wrong, diff + wrong);
    return diff + wrong != 0;
}
