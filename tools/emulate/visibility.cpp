// SIMT emulation (simt.hpp), on the CPU, of the visibility filter (visibilityKernel, src_cuda/visibility_filter.cu) in
// two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and new.inc): both filter the same
// random sparse map (scan lines with gaps or scattered points on bands of a few levels, a random density, up to the
// image's edges) with random window radii, parallax growth and threshold, the scan test's result on or off, in blocks
// of 32 x 32 over the map's rows listed as listSparseRows lists them (sparse_maps.hpp), and their maps are compared with
// each other and with a direct search of every point within the tile's margin by hiddenBy (pipeline.hpp), pixel by
// pixel.
#include "simt.hpp"
#include "cases.hpp"
#include "cuda_stages.hpp"
#include "sparse_window.cuh"

int* dynamicSmem;   // a block's dynamic shared memory (the blocks run one after another)

#include "versions.hpp"
#include "sparse_maps.hpp"

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int W = U(1, 110), H = U(1, 80);
    const bool lines = U(0, 1);
    const int lineStep = U(1, 8), density = U(1, 100);
    PipelineParams p{};
    p.numDisparities = 128;
    p.visibilityRadiusX = U(0, 4);
    p.visibilityRadiusY = U(0, 6);
    p.visibilityParallax256 = U(0, 2) == 0 ? 0 : U(1, 64);
    p.checkThreshold16 = U(0, 48);
    const bool withStats = U(0, 1), growthOn = U(0, 1);
    // Surfaces: bands of columns at a level each, a little noise on every point, so that both hidden and visible
    // points occur.
    const int band = U(1, 30), levels = U(1, 6);
    std::vector<int> level(levels);
    for (auto& l : level) l = U(0, 2000);
    std::vector<short> map((size_t)W * H, NO_DISP);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if ((!lines || y % lineStep == 0) && U(1, 100) <= density)
                map[(size_t)y * W + x] = (short)(level[x / band % levels] + U(0, 40));
    const ListedRows listed(map, W, H);
    const SparseRows rows = listed.rows;
    std::vector<int> stats(2 * SCAN_GAP_BINS + 1, 0);
    stats[2 * SCAN_GAP_BINS] = growthOn ? 1 : 0;
    const int* const st = withStats ? stats.data() : nullptr;
    const int reach = std::max(p.visibilityRadiusX, p.visibilityRadiusY) + visibilityGrowth(p);
    std::vector<int> smem(tilePointsBytes(32, 32, reach) / sizeof(int) + 2);
    dynamicSmem = smem.data();
    const cv::cuda::PtrStepSz<short> sparse(H, W, map.data(), W * sizeof(short));
    std::vector<short> out[2];
    const dim3 grid((W + 31) / 32, (H + 31) / 32);
    for (int v = 0; v < 2; v++)
    {
        out[v].assign((size_t)W * H, 12345);
        const cv::cuda::PtrStepSz<short> o(H, W, out[v].data(), W * sizeof(short));
        if (v == 0)
            launch(grid, dim3(32, 32), [&]() { oldv::visibilityKernel(sparse, rows, p, reach, st, o); });
        else
            launch(grid, dim3(32, 32), [&]() { newv::visibilityKernel(sparse, rows, p, reach, st, o); });
    }
    // Directly: a point is hidden by any point within the margin for which hiddenBy holds.
    PipelineParams q = p;
    if (withStats && !growthOn)
        q.visibilityParallax256 = 0;
    int diff = 0, wrong = 0, hidden = 0, points = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
        {
            const size_t i = (size_t)y * W + x;
            const int d = map[i];
            bool h = false;
            for (int v = std::max(y - reach, 0); d != NO_DISP && v <= std::min(y + reach, H - 1) && !h; v++)
                for (int u = std::max(x - reach, 0); u <= std::min(x + reach, W - 1) && !h; u++)
                    h = hiddenBy(map[(size_t)v * W + u], d, u - x, v - y, q);
            const short want = h ? NO_DISP : (short)d;
            points += d != NO_DISP;
            hidden += h;
            diff += out[0][i] != out[1][i];
            wrong += out[1][i] != want;
        }
    printf("seed %d: %dx%d %s, reach %d, %d points, %d hidden, %d pixels against the direct search, %d differ\n",
           U.seed, W, H, lines ? "lines" : "scattered", reach, points, hidden, wrong, diff + wrong);
    return diff + wrong != 0;
}
