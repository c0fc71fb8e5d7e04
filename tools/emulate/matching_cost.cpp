// SIMT emulation (simt.hpp), on the CPU, of the stored matching costs over the disparity windows (windowCostsKernel,
// src_cuda/matching_cost.cu) in two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and
// new.inc): both take the same random census strings, facts and windows (edge tiles included), with and without DDC,
// into a volume of garbage, and the volumes (the costs and the zeroed sums) are compared word for word.
#include "simt.hpp"
#include "cases.hpp"
#include "aggregation.cuh"
#include "cuda_stages.hpp"

#include "versions.hpp"
using namespace cv::lidarsgm::detail::cuda_impl::aggregation;

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int seed = U.seed;
    const int W = U(20, 140), H = U(10, 80), D = 16 * U(1, 8), minD = U(0, 3) == 0 ? U(1, 8) : 0;
    const bool ddc = U(0, 1);
    const int M = D + 16;   // the right strings' left margin
    const RandomCensus census(U.rng, W, H, M);
    const cv::cuda::PtrStepSz<int> censusL = census.left, censusR = census.right;
    std::vector<unsigned short> fa((size_t)W * H);
    for (auto& v : fa)
        v = (unsigned short)packFacts(U(0, D - 1), ddc ? U(0, 2) : 0, U(0, 15));
    cv::cuda::PtrStepSz<unsigned short> facts(H, W, fa.data(), W * sizeof(unsigned short));
    const int TX = (W + WINDOW_TILE - 1) / WINDOW_TILE, TY = (H + WINDOW_TILE - 1) / WINDOW_TILE;
    std::vector<int> tiles(TX * TY), bases(TX * TY + 1);
    for (int t = 0; t < TX * TY; t++)
    {
        const int lo = 16 * U(0, D / 16 - 1);
        tiles[t] = lo | std::min(D, lo + 16 * U(1, D / 16)) << 16;
        bases[t + 1] = bases[t] + ((tiles[t] >> 16) - (tiles[t] & 0xFFFF)) / WINDOW_ALIGN;
    }
    WindowMap windows;
    windows.tiles = cv::cuda::PtrStepSz<int>(TY, TX, tiles.data(), TX * sizeof(int));
    windows.bases = bases.data();
    const size_t shorts = windowVolumeShorts(bases[TX * TY], true);
    PipelineParams p{};
    p.minDisparity = minD; p.numDisparities = D; p.numPaths = 8;
    p.w.census256 = U(256, 2048); p.w.q1 = 70; p.w.q2 = 2240; p.w.p1 = 200; p.w.p2 = 2400; p.w.p2Edge = 1200;
    p.w.scale = 20;
    p.wCopy = p.w; p.wCopy.q1 = 35; p.wCopy.q2 = 1120;
    std::vector<unsigned> vols[2];
    for (int v = 0; v < 2; v++)
    {
        std::vector<unsigned> vol(shorts / 2 + 64, 0xABABABABu);   // uint4-aligned by the allocator (16 bytes)
        uint4* const sums = (uint4*)vol.data();
        uint4* const costs = (uint4*)windowCostsOf(vol.data(), shorts);
        const dim3 grid(TX, TY * (WINDOW_TILE / 8));
#define RUN(NS, DDC) \
        launch(grid, 8, [&]() { NS::windowCostsKernel<DDC>(censusL, censusR, facts, windows, p, sums, costs); })
        if (v == 0) { if (ddc) RUN(oldv, true); else RUN(oldv, false); }
        else { if (ddc) RUN(newv, true); else RUN(newv, false); }
        vols[v] = vol;
    }
    size_t diff = 0, zero = 0;
    for (size_t i = 0; i < vols[0].size(); i++) { diff += vols[0][i] != vols[1][i]; zero += vols[0][i] == 0; }
    printf("seed %d: %dx%d D %d minD %d ddc %d: %zu words, %zu zeroed, %zu differ\n", seed, W, H, D, minD, ddc,
           vols[0].size(), zero, diff);
    return diff != 0;
}
