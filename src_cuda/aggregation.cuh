// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Device helpers of the path kernel (src_cuda/aggregation.cu): the per-pixel facts, the DDC term table, the line
// geometry, the packed 16-bit minimum and census term; and the load of a pixel's cost pairs from the sum volume (the
// winner-takes-all's, src_cuda/winner_takes_all.cu).

#ifndef OPENCV_LIDARSGM_AGGREGATION_CUH
#define OPENCV_LIDARSGM_AGGREGATION_CUH

#include "opencv2/core/cuda_types.hpp"
#include "pipeline.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl { namespace aggregation {

using cv::cuda::PtrStepSz;

/* The per-pixel facts of a path step besides the census strings, packed into 16 bits (factsKernel) so that a step
 loads one warp-uniform value and tests no run-time flag:
 - bits 0-8: (k + 1) / 2, k the prior's disparity index (0 without a prior): one more than the index of the pair of
   disparities that holds k - 1, the first of the three disparities whose DDC term is not Q2;
 - bits 9-11: 2 c + (k & 1), c the prior's class (0 none, 1 measured, 2 copied: copiedPrior), which selects the row
   of the DDC term table (ddcPairTerm);
 - bits 12-15: bit b is intensityEdge between the pixel and its neighbour p - f_b, for the four forward directions
   f_0..f_3 = (1, 0), (0, 1), (1, 1), (-1, 1). The test is symmetric, so a path walking -f_b reads the bit of the
   previous pixel on its path. */
enum { FACT_PAIR_BITS = 9, FACT_ROW_SHIFT = 9, FACT_ROW_BITS = 3, FACT_EDGE_SHIFT = 12, FACT_ROWS = 6 };

//! k in [0, MAX_DISPARITIES) (the priors lie in the search range: sparseInRange), cls 0..2, edges 4 bits.
__host__ __device__ __forceinline__ unsigned packFacts(int k, int cls, unsigned edges)
{
    return cls == 0 ? edges << FACT_EDGE_SHIFT
                    : (unsigned)(k + 1) >> 1 | (unsigned)(2 * cls + (k & 1)) << FACT_ROW_SHIFT |
                      edges << FACT_EDGE_SHIFT;
}

/* The DDC terms (ddcTerm) of pair j of a run of G adjacent pairs of disparities, packed two per word, as a function
 of the facts' row (class and parity of k) and of u = pairs from the run's first pair to the pair that holds k - 1,
 plus one: u in [0, G] puts k - 1, k or k + 1 into the run; u = G + 1 stands for every run that none of them reaches.
 The offsets of the run's disparities from k depend on these alone, so a representative k of the row's parity gives
 them. */
__host__ __device__ __forceinline__ unsigned ddcPairTerm(int row, int u, int j, const CostWeights& w,
                                                         const CostWeights& wCopy)
{
    const int cls = row >> 1, k = 8 + (row & 1), pA = (k - 1) >> 1;
    const int e = 2 * (pA + 1 - u + j), kk = cls == 0 ? -1 : k;
    const CostWeights& wc = cls == 2 ? wCopy : w;
    return (unsigned)ddcTerm(e, kk, wc) | (unsigned)ddcTerm(e + 1, kk, wc) << 16;
}

/* The DDC terms of a group of G pairs (ddcPairTerm), by facts row and u in [0, G + 1], for one shared-memory load per
 group and step. A row takes 1 << FACT_ROW_SHIFT bytes, so that the facts' row bits are its offset. Ends with the
 block's barrier (before any thread of the block leaves). */
const int DDC_ROW_WORDS = (1 << FACT_ROW_SHIFT) / 4, DDC_TABLE_WORDS = FACT_ROWS * DDC_ROW_WORDS;
template <int G> __device__ __forceinline__ void fillDdcTable(unsigned* table, const PipelineParams& p)
{
    for (int i = threadIdx.x; i < FACT_ROWS * (G + 2) * G; i += blockDim.x)
    {
        const int row = i / ((G + 2) * G), u = i / G % (G + 2), j = i % G;
        table[row * DDC_ROW_WORDS + u * G + j] = ddcPairTerm(row, u, j, p.w, p.wCopy);
    }
    __syncthreads();
}

//! The row of a DDC table (fillDdcTable) for a pixel's facts f: its row bits are the row's byte offset.
__device__ __forceinline__ const unsigned* ddcRow(const unsigned* table, unsigned f)
{
    return (const unsigned*)((const char*)table + (f & ((1u << FACT_ROW_BITS) - 1) << FACT_ROW_SHIFT));
}

const unsigned BIG16 = 0x7FFF;    // stands for "no such disparity": above every path cost, never the minimum
const unsigned BIG16X2 = BIG16 * 0x10001u;

//! Both 16-bit halves' minima (min.u16x2: one instruction from sm_90 on).
__device__ __forceinline__ unsigned vmin2(unsigned a, unsigned b)
{
    return __vminu2(a, b);
}

/* censusTerm (pipeline.hpp) of two Hamming distances at once, h packed as h0 | h1 << 16: with census256 = 256 hi + lo,
 the term is hi h + (lo h + 128) / 256 (256 hi h is a multiple of 256). lo h + 128 < 2^16 (h <= 32), so one multiply
 gives both halves' lo products, whose bytes 1 and 3 are the quotients; hi h + quotient is the term itself, below 2^16
 since every cost is. No carry crosses between the halves. */
__device__ __forceinline__ unsigned censusTermPair(unsigned h, unsigned lo, unsigned hi)
{
    return h * hi + __byte_perm(h * lo + 0x00800080u, 0, 0x4341);
}

//! The lines of direction (dx, dy) in a W x H image: its rows, its columns, or W + H - 1 diagonals.
__host__ __device__ __forceinline__ int lineCount(int dx, int dy, int W, int H)
{
    return dy == 0 ? H : dx == 0 ? W : W + H - 1;
}

/* Line `line` (< lineCount) of direction (dx, dy): its first pixel. Horizontal lines are rows, vertical lines columns;
 diagonal lines start on the row the direction enters from (W lines), then on the column it enters from (H - 1
 lines). */
__device__ __forceinline__ void lineStart(int line, int dx, int dy, int W, int H, int& x, int& y)
{
    if (dy == 0)
    {
        y = line; x = dx > 0 ? 0 : W - 1;
    }
    else if (dx == 0)
    {
        x = line; y = dy > 0 ? 0 : H - 1;
    }
    else if (line < W)
    {
        x = line; y = dy > 0 ? 0 : H - 1;
    }
    else
    {
        x = dx > 0 ? 0 : W - 1; y = dy > 0 ? line - W + 1 : H - 1 - (line - W + 1);
    }
}

/* Direction dir (0..7) of the path kernels: (1,0) (-1,0) (0,1) (0,-1) (1,1) (-1,1) (1,-1) (-1,-1); computed, not a
 table (a table indexed by blockIdx would live in local memory). */
__host__ __device__ __forceinline__ void pathDirection(int dir, int& dx, int& dy)
{
    dx = dir < 2 ? 1 - 2 * dir : dir < 4 ? 0 : 1 - 2 * (dir & 1);
    dy = dir < 2 ? 0 : dir < 4 ? 5 - 2 * dir : dir < 6 ? 1 : -1;
}

/* The line a warp of the path kernels walks. Without `waves`, direction blockIdx.y, line block blockIdx.x. With
 `waves` (8 paths; a 1-D grid of 8 x lineBlocks blocks) the blocks take the horizontal directions first (the longest
 lines), then the three that go down, (0, 1), (1, 1), (-1, 1), in turn, line block by line block, then the three that
 go up the same way: the lines that start together run together, so the down-going lines that start on the top row
 reach each row at about the same time, and their sums' reductions meet in L2 instead of each reading and writing the
 row's sums in DRAM (pathKernel on the H100 at KITTI size: 0.92 GB of DRAM traffic against 1.26, 9 % less time).
 A block walks linesPerBlock lines, this thread line lineInBlock of them. Direction dir (pathDirection), line
 (lineStart) and its first pixel (x, y) and length n, the steps until it leaves the W x H image. False past the last
 line of the direction; with clampToLast, (x, y) and n are then the last line's (a warp whose lanes walk several lines
 keeps them all in its shuffles). */
__device__ __forceinline__ bool warpLine(int linesPerBlock, int lineInBlock, bool waves, int W, int H, int& dir,
                                         int& dx, int& dy, int& x, int& y, int& n, bool clampToLast = false)
{
    int lineBlock;
    if (waves)
    {
        const int lineBlocks = (int)gridDim.x / 8, b = (int)blockIdx.x;
        if (b < 2 * lineBlocks)
        {
            dir = b / lineBlocks;
            lineBlock = b % lineBlocks;
        }
        else
        {
            const int r = b - 2 * lineBlocks, wave = r / (3 * lineBlocks), k = r % (3 * lineBlocks) % 3;
            lineBlock = r % (3 * lineBlocks) / 3;
            dir = k == 0 ? 2 + wave : 3 + 2 * wave + k;   // 2, 4, 5 (down), then 3, 6, 7 (up)
        }
    }
    else
    {
        dir = (int)blockIdx.y;
        lineBlock = (int)blockIdx.x;
    }
    pathDirection(dir, dx, dy);
    const int line = lineBlock * linesPerBlock + lineInBlock, lines = lineCount(dx, dy, W, H);
    if (line >= lines && !clampToLast)
        return false;
    lineStart(::min(line, lines - 1), dx, dy, W, H, x, y);
    n = ::min(dx > 0 ? W - x : dx < 0 ? x + 1 : INT_MAX, dy > 0 ? H - y : dy < 0 ? y + 1 : INT_MAX);
    return line < lines;
}

/* The bit of the facts (packFacts) that holds direction dir's jump edge, in a word of the current pixel's facts low and
 the previous pixel's high: bit b of the current pixel for a forward direction, of the previous one (the pair's other
 pixel) for its opposite. */
__device__ __forceinline__ unsigned edgeMaskOf(int dir)
{
    const int edgeBit = dir < 2 ? 0 : dir < 4 ? 1 : (dir == 4 || dir == 7) ? 2 : 3;
    const bool edgeOfPrev = dir < 4 ? (dir & 1) != 0 : dir >= 6;
    return 1u << (FACT_EDGE_SHIFT + edgeBit + (edgeOfPrev ? 16 : 0));
}

/* Where a path kernel finds pixel s of its line: every step in memory has the sign of dy (or of dx on rows), so pixel
 s lies idx |step| bytes after the origin (xo, yo), idx = s walking forward, n - 1 - s from the line's last pixel
 otherwise: one unsigned multiply-add per address. idx starts at the line's first pixel and moves by dIdx. The steps,
 in bytes, of the left and right census strings, the facts and the sums (D per pixel). */
struct LineAddressing
{
    int xo, yo, dIdx, idx;
    unsigned stepL, stepR, stepF, stepS;
};

__device__ __forceinline__ LineAddressing lineAddressing(int x, int y, int dx, int dy, int n, size_t censusLStep,
                                                         size_t censusRStep, size_t factsStep, size_t sumStep, int D)
{
    const bool forward = dy > 0 || (dy == 0 && dx > 0);
    LineAddressing a;
    a.xo = forward ? x : x + (n - 1) * dx;
    a.yo = forward ? y : y + (n - 1) * dy;
    a.stepL = (unsigned)abs(dy * (int)censusLStep + dx * (int)sizeof(int));
    a.stepR = (unsigned)abs(dy * (int)censusRStep + dx * (int)sizeof(int));
    a.stepF = (unsigned)abs(dy * (int)factsStep + dx * (int)sizeof(ushort));
    a.stepS = (unsigned)abs(dy * (int)sumStep + dx * D * (int)sizeof(ushort));
    a.dIdx = forward ? 1 : -1;
    a.idx = forward ? 0 : n - 1;
    return a;
}

/* The path weights as a step uses them, both 16-bit halves at once (P1, P2, P2 across an edge) and the census weight
 split for censusTermPair; pinned in registers (the compiler would otherwise reload and rescale them from the
 parameters at every step). */
struct PairWeights
{
    unsigned p1x2, p2x2, p2Edgex2, c256lo, c256hi;
};

__device__ __forceinline__ PairWeights pairWeights(const CostWeights& w)
{
    PairWeights k = { (unsigned)w.p1 * 0x10001u, (unsigned)w.p2 * 0x10001u, (unsigned)w.p2Edge * 0x10001u,
                      (unsigned)w.census256 & 255u, (unsigned)w.census256 >> 8 };
    asm("" : "+r"(k.p1x2), "+r"(k.p2x2), "+r"(k.p2Edgex2), "+r"(k.c256lo), "+r"(k.c256hi));
    return k;
}

/* matchingCost's census term of a pair of disparities, both halves (censusTermPair of the Hamming distances between
 the left string l and the pair's right strings r0, r1): what every path kernel and the stored costs compute. */
__device__ __forceinline__ unsigned censusPairTerm(unsigned l, unsigned r0, unsigned r1, const PairWeights& wk)
{
    return censusTermPair(__byte_perm(popcount32(l ^ r0), popcount32(l ^ r1), 0x5410), wk.c256lo, wk.c256hi);
}

/* The first n of PPT consecutive pairs. PPT 2 and 4: one vector access, n = PPT (d0 = lane * 2 * PPT and the row
 offset x * D are multiples of 2 * PPT 16-bit values since D is a multiple of 16, so the address is aligned to the
 access size and the lane's run ends at or before D). PPT 1 and 3: one pair at a time (with PPT 3 the last active
 lane's run may pass D: n < PPT). */
template <int PPT> __device__ __forceinline__ void loadPairs(const unsigned* S, int n, unsigned (&v)[PPT])
{
    if (PPT == 8)
    {
        const uint4 a = *(const uint4*)S, b = *(const uint4*)(S + 4);
        v[0] = a.x; v[1 % PPT] = a.y; v[2 % PPT] = a.z; v[3 % PPT] = a.w;
        v[4 % PPT] = b.x; v[5 % PPT] = b.y; v[6 % PPT] = b.z; v[7 % PPT] = b.w;
    }
    else if (PPT == 4)
    {
        const uint4 a = *(const uint4*)S;
        v[0] = a.x; v[1 % PPT] = a.y; v[2 % PPT] = a.z; v[3 % PPT] = a.w;
    }
    else if (PPT == 2) { const uint2 a = *(const uint2*)S; v[0] = a.x; v[1 % PPT] = a.y; }
    else
    {
#pragma unroll
        for (int i = 0; i < PPT; i++)
            if (i < n)
                v[i] = S[i];
    }
}

}}}}} // namespace cv::lidarsgm::detail::cuda_impl::aggregation

#endif
