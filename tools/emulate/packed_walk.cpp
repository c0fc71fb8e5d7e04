// SIMT emulation, on the CPU, of the packed windows' path kernel (packedWindowPathKernel, src_cuda/aggregation.cu) in
// two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and new.inc): both walk the same
// random inputs (census strings, facts, windows in four patterns, 4 or 8 paths, 112 or 128 disparities, each of the
// kernel's instantiations), and their sum volumes are compared word for word under simt.hpp's emulation.
#include "simt.hpp"
#include "cases.hpp"
#include "aggregation.cuh"
#include "cuda_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {
using namespace aggregation;
size_t wideMul(unsigned a, unsigned b) { return (size_t)a * b; }
void reduceAddIf(bool p, unsigned* a, unsigned v) { if (p) atomicAdd(a, v); }
void reduceAddIf(bool p, unsigned* a, unsigned lo, unsigned hi)
{
    if (p) atomicAdd((unsigned long long*)a, (unsigned long long)lo | (unsigned long long)hi << 32);
}
}}}}
#include "versions.hpp"

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int seed = U.seed;
    const int W = U(40, 140), H = U(20, 80), D = U(0, 1) ? 128 : 112, minD = U(0, 3) == 0 ? U(1, 8) : 0;
    const int numPaths = U(0, 1) ? 8 : 4, mode = U(0, 3);
    const bool ddc = U(0, 1), edges = U(0, 1), stored = !ddc && U(0, 1);
    // census strings, the right one with a left margin of D + minD columns
    const int M = D + 16;
    const RandomCensus census(U.rng, W, H, M);
    const cv::cuda::PtrStepSz<int> censusL = census.left, censusR = census.right;
    std::vector<unsigned short> fa((size_t)W * H);
    for (auto& v : fa)
    {
        const int cls = ddc ? U(0, 2) : 0;
        v = (unsigned short)packFacts(U(0, D - 1), cls, edges ? U(0, 15) : 0);
    }
    cv::cuda::PtrStepSz<unsigned short> facts(H, W, fa.data(), W * sizeof(unsigned short));
    const int TX = (W + WINDOW_TILE - 1) / WINDOW_TILE, TY = (H + WINDOW_TILE - 1) / WINDOW_TILE;
    std::vector<int> tiles(TX * TY), bases(TX * TY + 1);
    // modes: 0 random windows; 1 one window everywhere; 2 full range; 3 windows near a common one
    const int glo = 16 * U(0, D / 16 - 1), ghi = std::min(D, glo + 16 * U(1, 4));
    for (int t = 0; t < TX * TY; t++)
    {
        int lo, hi;
        if (mode == 1) { lo = glo; hi = ghi; }
        else if (mode == 2) { lo = 0; hi = D; }
        else if (mode == 3) { lo = std::max(0, glo - 16 * U(0, 1)); hi = std::min(D, ghi + 16 * U(0, 1)); }
        else { lo = 16 * U(0, D / 16 - 1); hi = std::min(D, lo + 16 * U(1, D / 16)); }
        tiles[t] = lo | hi << 16;
    }
    for (int t = 0; t < TX * TY; t++) bases[t + 1] = bases[t] + ((tiles[t] >> 16) - (tiles[t] & 0xFFFF)) / WINDOW_ALIGN;
    WindowMap windows;
    windows.tiles = cv::cuda::PtrStepSz<int>(TY, TX, tiles.data(), TX * sizeof(int));
    windows.bases = bases.data();
    const size_t shorts = windowVolumeShorts(bases[TX * TY], stored);
    PipelineParams p{};
    p.minDisparity = minD; p.numDisparities = D; p.numPaths = numPaths;
    p.w.census256 = 1536; p.w.q1 = 70; p.w.q2 = 2240; p.w.p1 = 200; p.w.p2 = 2400; p.w.p2Edge = 1200; p.w.scale = 20;
    p.wCopy = p.w; p.wCopy.q1 = 35; p.wCopy.q2 = 1120;
    p.edgeThreshold = edges ? 8 : 0;
    std::vector<unsigned> vols[2];
    for (int v = 0; v < 2; v++)
    {
        std::vector<unsigned> vol(shorts / 2 + 64, 0);   // uint4-aligned by the allocator (16 bytes)
        unsigned* costs = stored ? windowCostsOf(vol.data(), shorts) : nullptr;
        if (stored)
        {
            std::mt19937 r2(seed * 7 + 1);
            for (unsigned* c = costs; c < vol.data() + shorts / 2; c++) *c = (r2() % 2500) | (r2() % 2500) << 16;
        }
        unsigned* volume = vol.data();
        // The grid of runPackedWindowPaths: 32 WARPS_PER_BLOCK / LW lines a block.
        const auto run = [&](int warps, int lw, auto kernel) {
            const int maxLines = numPaths == 8 ? W + H - 1 : std::max(W, H), perBlock = 32 * warps / lw;
            const int lineBlocks = (maxLines + perBlock - 1) / perBlock;
            launch(numPaths == 8 ? dim3(lineBlocks * 8) : dim3(lineBlocks, numPaths), warps, kernel);
        };
#define RUN(NS, A, B, C) run(NS::WARPS_PER_BLOCK, NS::PackedWindowWalk<A, B, C>::LW, [&]() { \
            NS::packedWindowPathKernel<A, B, C>(censusL, censusR, facts, windows, p, volume, costs); })
#define PICK(NS) \
        if (stored) { if (edges) RUN(NS, false, true, true); else RUN(NS, false, false, true); } \
        else if (ddc) { if (edges) RUN(NS, true, true, false); else RUN(NS, true, false, false); } \
        else { if (edges) RUN(NS, false, true, false); else RUN(NS, false, false, false); }
        if (v == 0) { PICK(oldv) } else { PICK(newv) }
        vols[v] = vol;
    }
    size_t diff = 0, nz = 0;
    for (size_t i = 0; i < vols[0].size(); i++) { diff += vols[0][i] != vols[1][i]; nz += vols[0][i] != 0; }
    printf("seed %d: %dx%d D %d minD %d paths %d mode %d ddc %d edges %d stored %d: %zu words, %zu nonzero, "
           "%zu differ\n", seed, W, H, D, minD, numPaths, mode, ddc, edges, stored, vols[0].size(), nz, diff);
    return diff != 0;
}
