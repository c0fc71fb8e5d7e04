// SIMT emulation (simt.hpp), on the CPU, of the scan test's histograms (scanGapHistogramKernel,
// src_cuda/visibility_filter.cu) in two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and
// new.inc): both take the same random sparse map (scan lines with gaps, or scattered points, of a random density, up
// to the image's edges), and their histograms are compared with each other and with the CPU's rowPointGap and
// columnPointGap (pipeline.hpp) bin for bin.
#include "simt.hpp"
#include "cases.hpp"
#include "cuda_stages.hpp"

#include "versions.hpp"

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int seed = U.seed;
    const int W = U(1, 150), H = U(1, 110);
    const bool lines = U(0, 1);
    const int lineStep = U(1, 40), density = U(1, 100);   // scan lines every lineStep rows; points per 100
    std::vector<short> map((size_t)W * H, NO_DISP);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if ((!lines || y % lineStep == 0) && U(1, 100) <= density)
                map[(size_t)y * W + x] = (short)U(0, 2047);
    cv::cuda::PtrStepSz<short> sparse(H, W, map.data(), W * sizeof(short));
    std::vector<int> cpu(2 * SCAN_GAP_BINS, 0);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (map[(size_t)y * W + x] != NO_DISP)
            {
                const int gr = rowPointGap(&map[(size_t)y * W], x, W), gc = columnPointGap(map.data(), W, x, y, W, H);
                if (gr >= 0) cpu[gr]++;
                if (gc >= 0) cpu[SCAN_GAP_BINS + gc]++;
            }
    std::vector<int> hist[2];
    for (int v = 0; v < 2; v++)
    {
        hist[v].assign(2 * SCAN_GAP_BINS + 1, 0);
        const int rows = v == 0 ? oldv::SCAN_LAUNCH_ROWS : newv::SCAN_LAUNCH_ROWS;
        const dim3 grid((W + 31) / 32, (H + rows - 1) / rows);
        int* const stats = hist[v].data();
        if (v == 0)
            launch(grid, dim3(32, rows), [&]() { oldv::scanGapHistogramKernel(sparse, stats); });
        else
            launch(grid, dim3(32, rows), [&]() { newv::scanGapHistogramKernel(sparse, stats); });
        hist[v].pop_back();
    }
    int diff = 0, wrong = 0, points = 0;
    for (int i = 0; i < 2 * SCAN_GAP_BINS; i++)
    {
        diff += hist[0][i] != hist[1][i];
        wrong += hist[1][i] != cpu[i];
        points += i < SCAN_GAP_BINS ? cpu[i] : 0;
    }
    printf("seed %d: %dx%d %s, %d row gaps, %d bins against the CPU's, %d differ\n", seed, W, H,
           lines ? "lines" : "scattered", points, wrong, diff + wrong);
    return diff + wrong != 0;
}
