// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CUDA stages, one file each (src_cuda/<stage>.cu), twins of the CPU stages of the same names
// (src/cpu_stages.hpp): the same rules (src/pipeline.hpp), so the outputs are identical. Called by
// src_cuda/cuda_pipeline.cpp. Every call only enqueues work on the given stream: no allocation, no synchronisation.
// Where a stage takes 8- or 16-bit (or integer or float) data, it has one overload per element type.

#ifndef OPENCV_LIDARSGM_CUDA_STAGES_HPP
#define OPENCV_LIDARSGM_CUDA_STAGES_HPP

#include "opencv2/core/cuda_types.hpp"
#include "opencv2/core/cuda.hpp"
#include <cuda_runtime.h>
#include <algorithm>
#include "pipeline.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

using cv::cuda::PtrStepSz;

//! counts: 3 ints of device memory, zeroed, that receive SparseCounts (measured, inRange, beyond); nullptr: not counted.
void convertSparse(PtrStepSz<ushort> sparse, int minDisparity, int numDisparities, PtrStepSz<short> sparse16,
                   int* counts, cudaStream_t stream);
void convertSparse(PtrStepSz<float> sparse, int minDisparity, int numDisparities, PtrStepSz<short> sparse16,
                   int* counts, cudaStream_t stream);

/** A sparse map's points row by row (listSparseRows), for the kernels that list a block's tile of them
(sparse_window.cuh): row y's points left to right from entries(y, 0) on, each (value << 16) | x; chunks(y, c) = { the
row's points left of column 32 c, the bits of columns 32 c to 32 c + 31 that hold one }, cols / 32 + 1 chunks a row
(the last one's count is the row's). entries: the map's size, CV_32SC1; chunks: its rows, CV_32SC2. */
struct SparseRows
{
    PtrStepSz<int2> chunks;
    PtrStepSz<int> entries;
};

//! The buffers of SparseRows for a map of size sz (created where needed).
inline SparseRows sparseRowsBuffers(cv::Size sz, cuda::GpuMat& chunks, cuda::GpuMat& entries)
{
    chunks.create(sz.height, sz.width / 32 + 1, CV_32SC2);
    entries.create(sz, CV_32SC1);
    return SparseRows{ chunks, entries };
}

//! Fills rows (sparseRowsBuffers of sparse16's size) with sparse16's points.
void listSparseRows(PtrStepSz<short> sparse16, const SparseRows& rows, cudaStream_t stream);

/** The scan test (visibilityGrowthApplies) on the sparse map: stats, 2 SCAN_GAP_BINS + 1 ints of device memory,
receives the gap histograms and, at stats[2 SCAN_GAP_BINS], the result (1: a LiDAR scan). */
void testScan(PtrStepSz<short> sparse16, int* stats, cudaStream_t stream);

/** The visibility filter (hiddenBy). stats: testScan's output where p.visibilityParallax256 > 0 (the growth applies
to scans only), else unused. rows: sparse16's (listSparseRows). */
void filterHiddenPoints(PtrStepSz<short> sparse16, const SparseRows& rows, const PipelineParams& p,
                        PtrStepSz<short> visible16, const int* stats, cudaStream_t stream);

/** The columns the path kernel reads before and after a row of right census strings: the right pixel of disparity
index d at x is x - minDisparity - d, for x in [0, W) and d in [0, numDisparities). */
inline int rightCensusPadBefore(const PipelineParams& p)
{
    return std::max(0, p.numDisparities - 1 + p.minDisparity);
}
inline int rightCensusPadAfter(const PipelineParams& p)
{
    return std::max(0, -p.minDisparity);
}

/** Both images in one launch. censusR is a view with padBefore readable columns before each row and padAfter after
it (an ROI of a wider buffer): they get the census strings of the row's end pixels (the clamped border), so that the
path kernel loads the strings of any disparity without a bounds check. */
void censusTransform(PtrStepSz<uchar> left, PtrStepSz<uchar> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR,
                     int padBefore, int padAfter, cudaStream_t stream);
void censusTransform(PtrStepSz<ushort> left, PtrStepSz<ushort> right, PtrStepSz<int> censusL,
                     PtrStepSz<int> censusR, int padBefore, int padAfter, cudaStream_t stream);

//! rows: sparse16's (listSparseRows).
void semidensify(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16, const SparseRows& rows,
                 const PipelineParams& p, PtrStepSz<short> semidense16, cudaStream_t stream);

/** Ring interpolation (pipeline.hpp) into semidense16's empty pixels; above and below are maps of the image's size,
stats RING_GAP_BINS + 1 ints of device memory (the gap histogram, then the gap limit): the ring check reads the maps
and stats[RING_GAP_BINS]. */
void interpolateRings(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                      const PipelineParams& p, PtrStepSz<short> semidense16, PtrStepSz<short> above,
                      PtrStepSz<short> below, int* stats, cudaStream_t stream);

/** The coarse pass's images (coarseDisparities): left and right reduced by COARSE_SCALE, in one launch. */
void coarseImages(PtrStepSz<uchar> left, PtrStepSz<uchar> right, PtrStepSz<uchar> coarseL, PtrStepSz<uchar> coarseR,
                  cudaStream_t stream);
void coarseImages(PtrStepSz<ushort> left, PtrStepSz<ushort> right, PtrStepSz<ushort> coarseL,
                  PtrStepSz<ushort> coarseR, cudaStream_t stream);

/** The disparity windows (searchWindows on the CPU): windows receives per WINDOW_TILE tile (lo, hi). prior16: the
call's prior map (may be empty); coarse: the coarse pass's integer disparities (coarse pixels), used where a tile has
no prior around it. ownRanges and coarseRanges: scratch of the windows' size. */
void searchWindows(PtrStepSz<short> prior16, PtrStepSz<short> coarse, const PipelineParams& p,
                   PtrStepSz<int2> ownRanges, PtrStepSz<int2> coarseRanges, PtrStepSz<short2> windows,
                   cudaStream_t stream);

/** The windows' compact sum volume: tile t (row-major over the tiles; those at the image's right and bottom edges
padded to a whole tile) holds its WINDOW_TILE^2 pixels' windows from bases[t] * WINDOW_VOLUME_UNIT sums on, pixel
(x, y) at ((y % T) * T + x % T) * (hi - lo) sums after that, disparity d at d - lo after the pixel's first: the
volume shrinks with the windows. A tile takes (hi - lo) / WINDOW_ALIGN units; bases[tiles] is the total. */
enum { WINDOW_VOLUME_UNIT = WINDOW_TILE * WINDOW_TILE * WINDOW_ALIGN };

/** Pairs of sums before the compact volume's first window and after its last: a step of the packed windows' path
kernel addresses the rows of the union of a warp's windows (PackedWindowWalk), up to 56 pairs before and after its
pixel's window, and reads there and adds zeros there rather than testing each row. */
enum { WINDOW_GUARD_PAIRS = 64 };

//! Pixel (x, y)'s first sum in the compact volume, counted in pairs of sums (hi - lo is even), of its tile's base.
LIDARSGM_HD size_t windowPairOffset(int base, int x, int y, int lo, int hi)
{
    return WINDOW_GUARD_PAIRS + (size_t)(unsigned)base * (WINDOW_VOLUME_UNIT / 2) +
           ((unsigned)y % WINDOW_TILE * WINDOW_TILE + (unsigned)x % WINDOW_TILE) * (unsigned)((hi - lo) >> 1);
}

/** The 16-bit values of a compact volume whose tiles take `units` (the bases' total), its guards included; twice that
where the windows' costs are stored in it too (windowCostsStored, windowCostsOf). */
static inline size_t windowVolumeShorts(size_t units, bool costsStored = false)
{
    return (units * WINDOW_VOLUME_UNIT + 4 * WINDOW_GUARD_PAIRS) * (costsStored ? 2 : 1);
}

/** The windows as the aggregation and the winner-takes-all read them: per tile lo | hi << 16 (windowWords) and the
compact volume's bases (windowPairOffset; tiles + 1 ints). tiles.data null: the full range, in the full layout (rows
of width * numDisparities sums). */
struct WindowMap
{
    PtrStepSz<int> tiles;
    const int* bases;
    //! Tile (tx, ty)'s base.
    LIDARSGM_HD int base(int tx, int ty) const { return bases[ty * tiles.cols + tx]; }
};

/** The compact volume's bases of the windows (lo | hi << 16 per tile): bases, tiles + 1 ints of device memory. */
void windowLayout(PtrStepSz<int> windows, int* bases, cudaStream_t stream);

/** aggregateCosts' inputs, the CPU's AggregationInputs (what a call does not have stays empty): the census strings;
the prior (data null: plain SGM); the left image of element type T, whose intensity steps give the jump penalty
(read only when p.edgeThreshold > 0); own16, the filtered sparse map where copied priors take p.wCopy (copiedPrior)
if the scan test's result at *scan (device memory) is non-zero (data null: w everywhere); the windows (tiles.data
null: the full range), each pixel's paths covering its tile's window only; smCount, the multiprocessors the stream's
kernels run on, which choose the path kernel's layout (0: streamSmCount's). */
template <typename T>
struct AggregationInputs
{
    PtrStepSz<int> censusL, censusR;
    PtrStepSz<short> prior16;
    PtrStepSz<T> left;
    PtrStepSz<short> own16;
    const int* scan = nullptr;
    WindowMap windows = WindowMap();
    int smCount = 0;
};

/** The multiprocessors that the stream's kernels may run on: its green context's (a partition of the device, CUDA
12.4 and later) where it has one, else the device's. */
int streamSmCount(cudaStream_t stream);

/** Whether a call with disparity windows on an image of this size stores the matching costs of its windows
(windowMatchingCosts) for the packed windows' path kernel: at 112 and 128 disparities (aggregateCosts then walks 8
lanes a line over the union of a warp's windows), where each of the sms multiprocessors that its stream's kernels run
on (streamSmCount) has many path lines to walk. Its compact volume then holds the sums in its first half and the costs,
in the same layout, in the second. */
bool windowCostsStored(const PipelineParams& p, cv::Size size, int sms);

/** The stored costs' place (windowCostsStored) in a compact volume of total 16-bit values, at least twice
windowVolumeShorts: its second half, 16-byte aligned. */
static inline unsigned* windowCostsOf(void* volume, size_t total)
{
    return (unsigned*)((ushort*)volume + total / 16 * 8);
}

/** aggregateCosts' outputs. sum: rows = image rows, cols = width * numDisparities; with windows, the compact volume
(WindowMap), of which only the windows' sums are zeroed and written; where windowCostsStored, costs: the second half
of that volume (windowCostsOf), which receives the windows' matching costs. facts (scratch): a map of the image's
size that receives each pixel's packed facts (the path kernel's input besides the census strings), needed where a
prior or the edge rule exists; it may be prior16's memory, which it then overwrites. */
struct AggregationOutputs
{
    PtrStepSz<ushort> sum;
    PtrStepSz<ushort> facts;
    unsigned* costs = nullptr;
};

/** All paths. The matching cost (matchingCost, pipeline.hpp) is computed as the paths walk, from the census strings
and the prior, except where out.costs is given (windowCostsStored): then once per pixel and window into it, and the
paths read it. */
void aggregateCosts(const AggregationInputs<uchar>& in, const PipelineParams& p, const AggregationOutputs& out,
                    cudaStream_t stream);
void aggregateCosts(const AggregationInputs<ushort>& in, const PipelineParams& p, const AggregationOutputs& out,
                    cudaStream_t stream);

/** The matching costs of every pixel's window (matchingCost, as pairs: censusTermPair and the DDC pair terms of its
facts, whose prior counts where ddc) into costs, in the sums' compact layout (windowPairOffset), and those sums
zeroed. Up to 128 disparities. */
void windowMatchingCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                         const PipelineParams& p, bool ddc, unsigned* sums, unsigned* costs, cudaStream_t stream);

//! winnerTakesAll's inputs: aggregateCosts' sums of an image of width x height, laid out as windows says.
struct WinnerInputs
{
    PtrStepSz<ushort> sum;
    int width = 0, height = 0;
    WindowMap windows = WindowMap();   //!< as aggregateCosts' (each pixel's winner within its window)
};

/** The winner-takes-all's maps, the CPU's WinnerMaps: dispRight the right-view disparity as on the CPU; nonUnique16
(data null: not written) the winners that fail the uniqueness check, NO_DISP elsewhere. */
struct WinnerMaps
{
    PtrStepSz<short> disp16, dispInt, dispRight, nonUnique16;
};

//! A right pixel's disparity from its key (cost << 16 | d, the minimum over the left pixels that reach it; all ones:
//! none reached it), as winnerTakesAll writes dispRight.
LIDARSGM_HD short rightKeyDisparity(unsigned key, int minDisparity)
{
    return (short)(key == 0xFFFFFFFFu ? NO_DISP : (int)(key & 0xFFFFu) + minDisparity);
}

/** rightKey (rows x width, int): the right view's (cost << 16 | d) minima; out.dispRight: their disparities, or no
data where the caller reads the keys itself (medianFilter's rightKey). */
void winnerTakesAll(const WinnerInputs& in, const PipelineParams& p, const WinnerMaps& out, PtrStepSz<int> rightKey,
                    cudaStream_t stream);

/** The disparity windows' buffers: the coarse pass's images (left, then right), census strings, sums and outputs
(disp16, dispInt, dispRight), right-view keys; the tiles' prior and coarse ranges; the windows (CV_16SC2) and their
compact volume's bases (windowLayout). */
struct WindowBuffers
{
    cv::cuda::GpuMat images, censusL, censusRPadded, sum, disp, key, ranges, windows, bases;
};

//! A windows map (CV_16SC2 per tile) as the kernels read it: one int per tile, lo | hi << 16; empty: none.
inline PtrStepSz<int> windowWords(const cv::cuda::GpuMat& windows)
{
    return windows.empty() ? PtrStepSz<int>() : PtrStepSz<int>(windows.rows, windows.cols, (int*)windows.data,
                                                               windows.step);
}

//! The windows of w as the kernels read them.
inline WindowMap windowMap(const WindowBuffers& w)
{
    return { windowWords(w.windows), w.bases.ptr<int>() };
}

/** The coarse pass (coarseDisparities on the CPU, on every call), searchWindows into w.windows and windowLayout into
w.bases: the only host code among the stages (it allocates w's buffers where their size changes;
src_cuda/cuda_pipeline.cpp). */
void enqueueSearchWindows(const cv::cuda::GpuMat& prior16, const cv::cuda::GpuMat& left,
                          const cv::cuda::GpuMat& right, const PipelineParams& p, WindowBuffers& w,
                          cudaStream_t stream);

/** Up to three maps of one size filtered in one launch: dst[i] = median3x3(src[i]). Where rightKey has data, the
third map's values are rightKeyDisparity(rightKey, minDisparity) (src[2] unused): the right view's keys filtered
without a pass that converts them first. */
struct MedianMaps
{
    PtrStepSz<short> src[3], dst[3];
    PtrStepSz<int> rightKey;
    int minDisparity;
};
void medianFilter(const MedianMaps& maps, int count, cudaStream_t stream);

//! The ring check's inputs (pipeline.hpp): interpolateRings' maps and gap limit (device memory), the winner-takes-all's
//! non-unique winners; gap == nullptr: off (the pipeline passes them only where ringCheckOn holds).
struct RingCheckMaps
{
    PtrStepSz<short> above, below, nonUnique16;
    const int* gap;
};

/** The check and the conversion to the output format, in one pass (one overload per output type). confidence:
written where p.confidence (outputConfidence, 0 where out has no disparity). rows: sparse16's (listSparseRows;
unused where sparse16 has no data). */
void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                      PtrStepSz<short> sparse16, const SparseRows& rows, const RingCheckMaps& rings,
                      const PipelineParams& p, PtrStepSz<short> out, PtrStepSz<float> confidence, cudaStream_t stream);
void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                      PtrStepSz<short> sparse16, const SparseRows& rows, const RingCheckMaps& rings,
                      const PipelineParams& p, PtrStepSz<float> out, PtrStepSz<float> confidence, cudaStream_t stream);

//! A 1/16-pixel map in the output format without any check (the semidense map of semidensify()).
void encodeOutput(PtrStepSz<short> disp16, int minDisparity, PtrStepSz<short> out, cudaStream_t stream);
void encodeOutput(PtrStepSz<short> disp16, int minDisparity, PtrStepSz<float> out, cudaStream_t stream);

/** LiDAR points (float, each `stride` floats after the previous, x y z first) to a sparse disparity map: disp (CV_32F,
written, 0 = none); with out16 non-empty, also its KITTI 16-bit encoding. PT = projection * lidarToCamera, row-major
3x4. */
void projectPoints(const float* points, int n, int stride, const double PT[12], double focalBaseline,
                   PtrStepSz<float> disp, PtrStepSz<ushort> out16, cudaStream_t stream);

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
