// SIMT emulation (simt.hpp), on the CPU, of the stereo-LiDAR consistency check (checkKernel,
// src_cuda/consistency_check.cu) in two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and
// new.inc): both check the same random case (a disparity map of a few surfaces with noise and holes, a right view
// that agrees or not within lrMaxDiff, a sparse map of scan lines or scattered points near or away from the surfaces,
// the ring check's maps or none, random radii and thresholds, either test alone or both, the confidence on or off)
// into both output types, in blocks of 8 x 32 over the sparse rows as listSparseRows lists them (sparse_maps.hpp),
// and their outputs and confidences are compared with each other value for value.
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
    const int W = U(1, 100), H = U(1, 90);
    PipelineParams p{};
    p.minDisparity = 0;
    p.numDisparities = 128;
    p.checkRadius = U(0, 20);
    p.checkThreshold16 = U(0, 48);
    p.semidenseRadius = U(0, 8);
    p.lrMaxDiff = U(0, 2);
    p.stereoCheck = U(0, 3) != 0;
    p.lidarCheck = U(0, 3) != 0;
    p.confidence = U(0, 1);
    const bool withSparse = U(0, 4) != 0, withRings = withSparse && U(0, 1), lines = U(0, 1);
    const int band = U(1, 30), levels = U(1, 5), holes = U(0, 30), lrBad = U(0, 60), density = U(1, 60);
    const int lineStep = U(1, 8), off = U(0, 3);
    std::vector<int> level(levels);
    for (auto& l : level) l = U(0, std::min(100, W / 2));   // most right matches inside the image
    // Surfaces of whole disparities: disp16 that with a sixteenth's noise, dispInt it, the right view its copy at
    // x - d, spoilt at random; the sparse map the surfaces with noise, off by a few pixels at random.
    std::vector<short> d16((size_t)W * H, NO_DISP), dInt((size_t)W * H, NO_DISP), dRight((size_t)W * H, NO_DISP);
    std::vector<short> sparse((size_t)W * H, NO_DISP), nonUnique((size_t)W * H, NO_DISP);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
        {
            const size_t i = (size_t)y * W + x;
            const int d = level[x / band % levels];
            if (U(1, 100) > holes)
            {
                d16[i] = (short)(16 * d + U(-8, 7));
                dInt[i] = (short)d;
                if (x - d >= 0)
                    dRight[(size_t)y * W + x - d] = (short)(U(1, 100) > lrBad ? d + U(-1, 1) : U(0, 127));
            }
            else
                nonUnique[i] = U(0, 1) ? (short)(16 * d + U(-20, 20)) : NO_DISP;
            if (withSparse && (!lines || y % lineStep == 0) && U(1, 100) <= density)
                sparse[i] = (short)(16 * (d + (U(0, 3) == 0 ? U(-off, off) : 0)) + U(-16, 16));
        }
    ListedRows listed(sparse, W, H);
    RingNeighbours nb(sparse, W, H);
    int gap = U(1, 40);
    using cv::cuda::PtrStepSz;
    const auto map = [&](std::vector<short>& m) { return PtrStepSz<short>(H, W, m.data(), W * sizeof(short)); };
    RingCheckMaps rings = {};
    if (withRings)
        rings = { map(nb.above), map(nb.below), map(nonUnique), &gap };
    const PtrStepSz<short> sp = withSparse ? map(sparse) : PtrStepSz<short>();
    std::vector<int> smem(tilePointsBytes(8, 32, oldv::listRadius(p)) / sizeof(int) + 2);
    dynamicSmem = smem.data();
    const dim3 grid((W + 7) / 8, (H + 31) / 32), block(8, 32);
    std::vector<short> out16[2];
    std::vector<float> out32[2], conf[2];
    for (int v = 0; v < 2; v++)
    {
        out16[v].assign((size_t)W * H, 12345);
        out32[v].assign((size_t)W * H, -7.f);
        conf[v].assign((size_t)W * H, -3.f);
        const PtrStepSz<short> o16(H, W, out16[v].data(), W * sizeof(short));
        const PtrStepSz<float> o32(H, W, out32[v].data(), W * sizeof(float));
        const PtrStepSz<float> c = p.confidence ? PtrStepSz<float>(H, W, conf[v].data(), W * sizeof(float))
                                                : PtrStepSz<float>();
        const auto d1 = map(d16), d2 = map(dInt), d3 = map(dRight);
        if (v == 0)
        {
            launch(grid, block, [&]() { oldv::checkKernel<short>(d1, d2, d3, sp, listed.rows, rings, p, o16, c); });
            launch(grid, block, [&]() { oldv::checkKernel<float>(d1, d2, d3, sp, listed.rows, rings, p, o32, c); });
        }
        else
        {
            launch(grid, block, [&]() { newv::checkKernel<short>(d1, d2, d3, sp, listed.rows, rings, p, o16, c); });
            launch(grid, block, [&]() { newv::checkKernel<float>(d1, d2, d3, sp, listed.rows, rings, p, o32, c); });
        }
    }
    int diff = 0, kept = 0, valid = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
    {
        diff += out16[0][i] != out16[1][i] || memcmp(&out32[0][i], &out32[1][i], sizeof(float)) != 0 ||
                memcmp(&conf[0][i], &conf[1][i], sizeof(float)) != 0;
        valid += d16[i] != NO_DISP;
        kept += out16[1][i] != -16;
    }
    printf("seed %d: %dx%d%s%s%s%s, %d of %d disparities kept, %d differ\n", U.seed, W, H,
           p.stereoCheck ? " left-right" : "", p.lidarCheck ? " LiDAR" : "", withRings ? " rings" : "",
           p.confidence ? " confidence" : "", kept, valid, diff);
    return diff != 0;
}
