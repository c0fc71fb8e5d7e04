// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Matching cost over the disparity windows, CUDA twin of src/matching_cost.simd.hpp (matchingCost, pipeline.hpp): the
// costs of every pixel's window, stored once for the packed windows' path kernel (src_cuda/aggregation.cu), which
// otherwise computes them again in each of its directions.

#include "cuda_stages.hpp"
#include "aggregation.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

using namespace aggregation;

const int BAND_ROWS = 8, THREADS = 256;   // a block: a band of 8 rows of a tile

/* A block per band of BAND_ROWS rows of a tile, whose pixels' windows follow each other in the compact layout
 (windowPairOffset), four pairs a thread and step (16-byte stores, consecutive across the threads). The pairs are
 computed as the path kernels compute them: censusTermPair of the two Hamming distances, and the DDC pair term from the
 table row of the pixel's facts, at u = the pairs from this pair to the one that holds the prior's k - 1, plus one,
 clamped to 2. The sums of the same pixels are zeroed. */
template <bool DDC>
__global__ void __launch_bounds__(THREADS)
windowCostsKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                  PipelineParams p, uint4* sums, uint4* costs)
{
    __shared__ __align__(8) unsigned ddcTable[DDC ? DDC_TABLE_WORDS : 1];
    if (DDC)
        fillDdcTable<1>(ddcTable, p);
    const int W = censusL.cols, H = censusL.rows, tx = blockIdx.x;
    const int ty = blockIdx.y / (WINDOW_TILE / BAND_ROWS), band = blockIdx.y % (WINDOW_TILE / BAND_ROWS);
    const unsigned w = (unsigned)windows.tiles(ty, tx);
    const int lo = (int)(w & 0xFFFFu), hi = (int)(w >> 16);
    const int quads = (hi - lo) / 8;   // a pixel's runs of four pairs (windows are multiples of 16 wide, at least 16)
    // i / quads as the high word of a product, exact for i < 2^32 / quads.
    const unsigned magic = (unsigned)((0x100000000ull + quads - 1) / quads);
    const int x0 = tx * WINDOW_TILE, y0 = ty * WINDOW_TILE + band * BAND_ROWS;
    const size_t first = windowPairOffset(windows.base(tx, ty), x0, y0, lo, hi) / 4;
    const PairWeights wk = pairWeights(p.w);
    for (int i = threadIdx.x; i < BAND_ROWS * WINDOW_TILE * quads; i += THREADS)
    {
        const int pixel = (int)__umulhi((unsigned)i, magic), q = i - pixel * quads;
        const int x = x0 + pixel % WINDOW_TILE, y = y0 + pixel / WINDOW_TILE, d0 = lo + 8 * q;
        if (x >= W || y >= H)   // an edge tile's padding: never read
            continue;
        const unsigned l = (unsigned)censusL(y, x);
        const int* R = censusR.ptr(y) + x - p.minDisparity - d0;   // R[-e]: disparity index d0 + e
        unsigned a = 0;
        const unsigned* row = ddcTable;
        if (DDC)
        {
            const unsigned f = facts(y, x);
            a = (f & ((1u << FACT_PAIR_BITS) - 1)) - (unsigned)(d0 >> 1);
            row = ddcTable + (f >> FACT_ROW_SHIFT & ((1u << FACT_ROW_BITS) - 1)) * DDC_ROW_WORDS;
        }
        unsigned c[4];
#pragma unroll
        for (int j = 0; j < 4; j++)
        {
            c[j] = censusPairTerm(l, (unsigned)R[-2 * j], (unsigned)R[-2 * j - 1], wk) +
                   (DDC ? row[::min(a - (unsigned)j, 2u)] : 0u);
        }
        costs[first + i] = make_uint4(c[0], c[1], c[2], c[3]);
        sums[first + i] = make_uint4(0, 0, 0, 0);
    }
}

} // namespace

void windowMatchingCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                         const PipelineParams& p, bool ddc, unsigned* sums, unsigned* costs, cudaStream_t stream)
{
    const dim3 grid(windows.tiles.cols, windows.tiles.rows * (WINDOW_TILE / BAND_ROWS));
    auto kernel = ddc ? windowCostsKernel<true> : windowCostsKernel<false>;
    kernel<<<grid, THREADS, 0, stream>>>(censusL, censusR, facts, windows, p, (uint4*)sums, (uint4*)costs);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
