// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.simd.hpp, with the matching cost (src/matching_cost.simd.hpp on
// the CPU) computed as the paths walk. Three sweeps over the one 16-bit sum volume, without atomics:
//  - the horizontal pass: one warp per row walks both horizontal directions at once, from both ends; the first visit
//    of a pixel stores its path costs, the second adds its own;
//  - the down pass: the vertical and both downward diagonals, which share each pixel's matching cost and loads; adds
//    them to the sums;
//  - the up pass: the three upward directions likewise.
// In the vertical passes one warp holds one column and a block a strip of columns; the diagonals' path costs move to
// the neighbouring column every row, through shared memory inside a strip. Between strips they are handed off once
// every R rows only: a strip also walks the diagonals of the R - 1 columns on each side that reach it within the
// chunk (a trapezoid), from the path costs its neighbours left at the chunk's start.

#include "cuda_stages.hpp"
#include "aggregation.cuh"
#include "opencv2/cudev/common.hpp"
#include <algorithm>

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

using namespace aggregation;

const int ROWS_PER_BLOCK = 4;   // horizontal pass: warps per block, two per row
const int STRIP_WARPS = 32;     // vertical passes with diagonals: warps (columns) per block, halos included
const int COLUMN_WARPS = 4;     // vertical passes without diagonals (4 paths)
const int CHUNK_ROWS = 8;       // rows between hand-offs: the halo is CHUNK_ROWS - 1 columns on each side
const int SUM_AHEAD = 4;        // vertical passes: rows of sums in flight (cp.async) ahead of the row being added to

//! Word offset of pair i of this lane within a pixel's D / 2 words (Lanes).
template <int PPT, int G> __device__ __forceinline__ int pairWord(const Lanes<PPT, G>& ln, int i)
{
    return 32 * G * (i / G) + G * ln.lane + i % G;
}

//! The lane's pairs from D / 2 words at p (pairs that hold no disparities: left as they are). LOAD: a load function.
template <int PPT, int G, typename Load>
__device__ __forceinline__ void loadWords(const Lanes<PPT, G>& ln, const unsigned* p, unsigned (&v)[PPT], Load load)
{
#pragma unroll
    for (int g = 0; g < Lanes<PPT, G>::NG; g++)
        if (ln.holds(G * g))
        {
            if (G == 2)
            {
                const uint2 a = load((const uint2*)(p + pairWord(ln, G * g)));
                v[G * g] = a.x;
                v[(G * g + 1) % PPT] = a.y;
            }
            else
                v[G * g] = load(p + pairWord(ln, G * g));
        }
}

template <int PPT, int G, typename Store>
__device__ __forceinline__ void storeWords(const Lanes<PPT, G>& ln, unsigned* p, const unsigned (&v)[PPT], Store store)
{
#pragma unroll
    for (int g = 0; g < Lanes<PPT, G>::NG; g++)
        if (ln.holds(G * g))
        {
            if (G == 2)
                store((uint2*)(p + pairWord(ln, G * g)), make_uint2(v[G * g], v[(G * g + 1) % PPT]));
            else
                store(p + pairWord(ln, G * g), v[G * g]);
        }
}

struct Plain
{
    template <typename V> __device__ __forceinline__ V operator()(const V* p) const { return *p; }
    template <typename V> __device__ __forceinline__ void operator()(V* p, V v) const { *p = v; }
};
//! Through L2 only: the hand-off words are written by other blocks, whose writes L1 does not see.
struct L2Only
{
    template <typename V> __device__ __forceinline__ V operator()(const V* p) const { return __ldcg(p); }
    template <typename V> __device__ __forceinline__ void operator()(V* p, V v) const { __stcg(p, v); }
};

template <int PPT> __device__ __forceinline__ void addPairs(unsigned (&s)[PPT], const unsigned (&v)[PPT])
{
#pragma unroll
    for (int i = 0; i < PPT; i++)
        s[i] += v[i];   // 16-bit halves: the sums stay below 2^16 (computeCostWeights), no carry between them
}

//! Asynchronous copies global -> shared of the lane's pairs (cp.async: the warp does not wait for them until waitCopies).
template <int PPT, int G>
__device__ __forceinline__ void copyWordsAsync(const Lanes<PPT, G>& ln, unsigned* dst, const unsigned* src)
{
#pragma unroll
    for (int g = 0; g < Lanes<PPT, G>::NG; g++)
        if (ln.holds(G * g))
        {
            const unsigned d = (unsigned)__cvta_generic_to_shared(dst + pairWord(ln, G * g));
            const unsigned* q = src + pairWord(ln, G * g);
            if (G == 2)
                asm volatile("cp.async.ca.shared.global [%0], [%1], 8;" ::"r"(d), "l"(q) : "memory");
            else
                asm volatile("cp.async.ca.shared.global [%0], [%1], 4;" ::"r"(d), "l"(q) : "memory");
        }
}
__device__ __forceinline__ void commitCopies() { asm volatile("cp.async.commit_group;" ::: "memory"); }
//! Waits until at most N of this thread's committed copy groups are still in flight.
template <int N> __device__ __forceinline__ void waitCopies() { asm volatile("cp.async.wait_group %0;" ::"n"(N) : "memory"); }

__device__ __forceinline__ int ldAcquire(const int* p)
{
    int v;
    asm volatile("ld.acquire.gpu.global.b32 %0, [%1];" : "=r"(v) : "l"(p) : "memory");
    return v;
}
__device__ __forceinline__ void stRelease(int* p, int v)
{
    asm volatile("st.release.gpu.global.b32 [%0], %1;" ::"l"(p), "r"(v) : "memory");
}

//! The pixel's row of the sum volume as words.
__device__ __forceinline__ unsigned* sumsAt(PtrStepSz<ushort> sum, int D, int x, int y)
{
    return (unsigned*)(sum.ptr(y) + (size_t)x * D);
}

//! One direction's walker state along a row: its path costs, their minimum and the previous pixel's intensity.
template <int PPT> struct Walk
{
    PixelIn<PPT> next;
    unsigned P[PPT];
    int minPrev, prevIntensity;
};

template <int PPT, int G, typename T>
__device__ __forceinline__ void walkStep(const PathInputs<T>& in, const Lanes<PPT, G>& ln, bool copies, int y, bool start,
                                         int xNext, Walk<PPT>& wk)
{
    unsigned Cp[PPT];
    pairCosts(in, ln, copies, wk.next, Cp);
    const int cur = wk.next.intensity;
    if (xNext >= 0)
        in.load(ln, copies, xNext, y, wk.next);   // issued before the recurrence, to hide its latency
    if (start)
    {
#pragma unroll
        for (int i = 0; i < PPT; i++)
            wk.P[i] = Cp[i];
    }
    else
    {
        unsigned Pn[PPT];
        pathStep(ln, wk.P, Cp, wk.minPrev, jumpPenalty(cur, wk.prevIntensity, in.edgeThreshold, in.w), in.w.p1, Pn);
#pragma unroll
        for (int i = 0; i < PPT; i++)
            wk.P[i] = Pn[i];
    }
    wk.minPrev = pathMin(ln, wk.P);
    wk.prevIntensity = cur;
}

/* The horizontal pass: two warps per row, one walking (1, 0) from the left end and one (-1, 0) from the right end. The
 left walker stores its path costs on the row's left half (the first visit of those pixels) and adds its own to the
 right walker's on the right half, and the other way round. A walker adds at a pixel only after the other has stored
 there: each publishes in shared memory how many steps it has taken (lane 0, after a block-scope fence), and the
 other waits for it, which costs a load a step once they have passed each other. */
template <int PPT, int G, typename T>
__global__ void __launch_bounds__(32 * ROWS_PER_BLOCK) horizontalKernel(PathInputs<T> in, PtrStepSz<ushort> sum)
{
    __shared__ int steps[ROWS_PER_BLOCK];
    const Lanes<PPT, G> ln(in.D);
    const int warp = threadIdx.x >> 5, y = blockIdx.x * (ROWS_PER_BLOCK / 2) + (warp >> 1);
    const int W = in.censusL.cols, D = in.D, xm = W / 2;
    const bool right = warp & 1;   // walks (-1, 0)
    volatile int* other = steps + (warp ^ 1);
    if (ln.lane == 0)
        steps[warp] = 0;
    __syncthreads();
    if (y >= in.censusL.rows)
        return;
    const bool copies = in.own16.data && *in.scan != 0;
    Walk<PPT> a;
    in.load(ln, copies, right ? W - 1 : 0, y, a.next);
    for (int s = 0; s < W; s++)
    {
        const int x = right ? W - 1 - s : s;
        walkStep(in, ln, copies, y, s == 0, s + 1 < W ? (right ? x - 1 : x + 1) : -1, a);
        const bool first = right ? x >= xm : x < xm;   // this walker stores (the other adds)
        unsigned* S = sumsAt(sum, D, x, y);
        if (first)
        {
            if (ln.active)
                storeWords(ln, S, a.P, Plain());
            __threadfence_block();
            __syncwarp();
            if (ln.lane == 0)
                *(volatile int*)(steps + warp) = s + 1;
        }
        else
        {
            // The other walker stores x at its step W - 1 - s: wait until it has taken W - s steps.
            if (ln.lane == 0)
                while (*other < W - s)
                {
                }
            __syncwarp();
            if (ln.active)
            {
                unsigned v[PPT];
                loadWords(ln, S, v, Plain());
                addPairs(v, a.P);
                storeWords(ln, S, v, Plain());
            }
        }
    }
}

/* The vertical passes' hand-off between row chunks (NDIR 3): for each parity of the chunk index, direction (vertical,
 (1, dy), (-1, dy)) and column, the path costs of the chunk's last row (D / 2 words) and their minimum; the chunks
 completed per strip; the next work item. */
struct HandOff
{
    unsigned* costs;
    int* minima;
    int* done;
    int* ticket;
};

/* A vertical pass, down (dy 1) or up (dy -1): the vertical direction, and with NDIR 3 both diagonals (1, dy) and
 (-1, dy). Work items are (row chunk, strip) in that order, taken from a counter, so that an item only waits for items
 taken before it by running blocks (never for blocks that are not resident). With NDIR 3 the block's warps hold
 columns s Ws - halo + w; owners (the strip's Ws columns) walk all three directions and add their sums, the halo
 warps walk the diagonal that reaches the strip within the chunk: (1, dy) on the left, (-1, dy) on the right. The
 diagonals' path costs go to the next row's neighbour through shared memory (double-buffered by row parity); at the
 chunk's start they come from the hand-off, which the neighbouring strips wrote at the end of the chunk before. */
template <int PPT, int G, int NDIR, typename T>
__global__ void __launch_bounds__(32 * STRIP_WARPS)
verticalKernel(PathInputs<T> in, PtrStepSz<ushort> sum, int dy, int R, HandOff h)
{
    // [row parity][diagonal][warp][D / 2] path costs (NDIR 3), their minima, then [warp][SUM_AHEAD][D / 2] sums
    extern __shared__ unsigned smem[];
    __shared__ int item;
    __shared__ int rowsDone[STRIP_WARPS];   // per warp: the rows of the item it has finished
    const Lanes<PPT, G> ln(in.D);
    const int nw = blockDim.x >> 5, w = threadIdx.x >> 5;
    const int W = in.censusL.cols, H = in.censusL.rows, D = in.D, DW = D / 2;
    const int halo = NDIR == 3 ? R - 1 : 0, Ws = nw - 2 * halo;
    const int strips = (W + Ws - 1) / Ws, chunks = (H + R - 1) / R, items = strips * chunks;
    const bool copies = in.own16.data && *in.scan != 0;
    int* smin = (int*)(smem + (NDIR == 3 ? 4 * nw * DW : 0));
    // The sums of the rows ahead, fetched asynchronously: the read-modify-write does not wait for memory.
    unsigned* sumRing = smem + (NDIR == 3 ? 4 * nw * (DW + 1) : 0) + (size_t)w * SUM_AHEAD * DW;
    const int yFirst = dy > 0 ? 0 : H - 1;
    const int p1 = in.w.p1;
    for (;;)
    {
        if (threadIdx.x == 0)
            item = atomicAdd(h.ticket, 1);
        __syncthreads();   // also: every warp has finished the previous item
        const int t = item;
        if (t >= items)
            return;
        if (ln.lane == 0)
            rowsDone[w] = 0;
        const int k = t / strips, s = t - k * strips;
        if (NDIR == 3 && k > 0 && threadIdx.x == 0)
        {
            for (int n = ::max(0, s - 1); n <= ::min(strips - 1, s + 1); n++)
                while (ldAcquire(h.done + n) < k)
                {
                }
        }
        __syncthreads();
        const int c = s * Ws - halo + w;
        const bool inImg = c >= 0 && c < W;   // warp-uniform, like everything that decides a branch below
        const bool owner = inImg && w >= halo && w < halo + Ws;
        const int y0 = yFirst + dy * k * R, rows = ::min(R, H - k * R);
        const int prevPar = (k + 1) & 1;   // the hand-off parity of chunk k - 1
        PixelIn<PPT> px;
        int predNext[3] = { 0, 0, 0 };   // intensities of the predecessors (c - 1, c, c + 1) on the row before
        // Rows 0 .. SUM_AHEAD - 2 of the sums in flight, one copy group each (empty where there is no such row, so
        // that group i is always row i's).
        for (int j = 0; j < SUM_AHEAD - 1; j++)
        {
            if (owner && j < rows)
                copyWordsAsync(ln, sumRing + j * DW, sumsAt(sum, D, c, y0 + dy * j));
            commitCopies();
        }
        if (inImg)
        {
            in.load(ln, copies, c, y0, px);
            if (in.edges && y0 != yFirst)
            {
#pragma unroll
                for (int j = 0; j < 3; j++)
                    predNext[j] = in.intensity(c - 1 + j, y0 - dy);
            }
        }
        unsigned Pv[PPT], Pa[PPT], Pb[PPT];
        int mv = 0;
        for (int i = 0; i < rows; i++)
        {
            const int y = y0 + dy * i, par = i & 1;
            const bool aOn = NDIR == 3 && inImg && w >= i && w < halo + Ws;
            const bool bOn = NDIR == 3 && inImg && w < nw - i && w >= halo;
            if (NDIR == 3 && i > 0)
            {
                // Row i reads the neighbours' row i - 1 and overwrites the buffer they read at row i - 1: wait
                // until both have finished it (the warps of a block drift apart by one row at most).
                if (ln.lane == 0)
                {
                    const volatile int* done = rowsDone;
                    while ((w > 0 && done[w - 1] < i) || (w + 1 < nw && done[w + 1] < i))
                    {
                    }
                }
                __syncwarp();
            }
            if (owner || aOn || bOn)
            {
                unsigned Cp[PPT];
                pairCosts(in, ln, copies, px, Cp);
                const int cur = px.intensity;
                int pred[3];
#pragma unroll
                for (int j = 0; j < 3; j++)
                    pred[j] = predNext[j];
                if (i + 1 < rows)
                {
                    in.load(ln, copies, c, y + dy, px);
                    if (in.edges)
                    {
#pragma unroll
                        for (int j = 0; j < 3; j++)
                            predNext[j] = in.intensity(c - 1 + j, y);
                    }
                }
                const bool start = y == yFirst;
                unsigned Pp[PPT];
                int m;
                if (owner)
                {
                    if (start)
                    {
#pragma unroll
                        for (int j = 0; j < PPT; j++)
                            Pv[j] = Cp[j];
                    }
                    else
                    {
                        if (i == 0)
                        {
                            loadWords(ln, h.costs + (size_t)((prevPar * 3 + 0) * W + c) * DW, Pp, L2Only());
                            m = __ldcg(h.minima + (prevPar * 3 + 0) * W + c);
                        }
                        else
                        {
#pragma unroll
                            for (int j = 0; j < PPT; j++)
                                Pp[j] = Pv[j];
                            m = mv;
                        }
                        pathStep(ln, Pp, Cp, m, jumpPenalty(cur, pred[1], in.edgeThreshold, in.w), p1, Pv);
                    }
                    mv = pathMin(ln, Pv);
                }
                // The diagonals: e = 0 is (1, dy), whose predecessor is column c - 1; e = 1 is (-1, dy), from c + 1.
#pragma unroll
                for (int e = 0; e < (NDIR == 3 ? 2 : 0); e++)
                {
                    if (!(e == 0 ? aOn : bOn))
                        continue;
                    unsigned (&P)[PPT] = e == 0 ? Pa : Pb;
                    const int cp = e == 0 ? c - 1 : c + 1;
                    if (start || cp < 0 || cp >= W)
                    {
#pragma unroll
                        for (int j = 0; j < PPT; j++)
                            P[j] = Cp[j];
                    }
                    else
                    {
                        if (i == 0)
                        {
                            loadWords(ln, h.costs + (size_t)((prevPar * 3 + 1 + e) * W + cp) * DW, Pp, L2Only());
                            m = __ldcg(h.minima + (prevPar * 3 + 1 + e) * W + cp);
                        }
                        else
                        {
                            const int src = ((1 - par) * 2 + e) * nw + (e == 0 ? w - 1 : w + 1);
                            loadWords(ln, smem + (size_t)src * DW, Pp, Plain());
                            m = smin[src];
                        }
                        pathStep(ln, Pp, Cp, m, jumpPenalty(cur, pred[2 * e], in.edgeThreshold, in.w), p1, P);
                    }
                    const int mn = pathMin(ln, P);
                    const int dst = (par * 2 + e) * nw + w;
                    storeWords(ln, smem + (size_t)dst * DW, P, Plain());
                    if (ln.lane == 0)
                        smin[dst] = mn;
                    if (owner && i == rows - 1 && k + 1 < chunks)
                    {
                        const int o = ((k & 1) * 3 + 1 + e) * W + c;
                        storeWords(ln, h.costs + (size_t)o * DW, P, L2Only());
                        if (ln.lane == 0)
                            __stcg(h.minima + o, mn);
                    }
                }
                if (owner)
                {
                    // Row i + SUM_AHEAD - 1 into the slot row i - 1 used; then row i's group is complete.
                    const int ahead = i + SUM_AHEAD - 1;
                    if (ahead < rows)
                        copyWordsAsync(ln, sumRing + (ahead % SUM_AHEAD) * DW, sumsAt(sum, D, c, y0 + dy * ahead));
                    commitCopies();
                    waitCopies<SUM_AHEAD - 1>();
                    unsigned Scur[PPT];
                    loadWords(ln, sumRing + (i % SUM_AHEAD) * DW, Scur, Plain());
                    addPairs(Scur, Pv);
                    if (NDIR == 3)
                    {
                        addPairs(Scur, Pa);
                        addPairs(Scur, Pb);
                        if (i == rows - 1 && k + 1 < chunks)
                        {
                            const int o = ((k & 1) * 3) * W + c;
                            storeWords(ln, h.costs + (size_t)o * DW, Pv, L2Only());
                            if (ln.lane == 0)
                                __stcg(h.minima + o, mv);
                        }
                    }
                    storeWords(ln, sumsAt(sum, D, c, y), Scur, Plain());
                }
            }
            if (NDIR == 3)
            {
                __threadfence_block();   // this row's shared-memory path costs before the count that releases them
                __syncwarp();
                if (ln.lane == 0)
                    *(volatile int*)(rowsDone + w) = i + 1;
            }
        }
        if (NDIR == 3 && k + 1 < chunks)
        {
            // Every thread's hand-off writes before the flag that releases them (bar.sync orders them in the block).
            __threadfence();
            __syncthreads();
            if (threadIdx.x == 0)
                stRelease(h.done + s, k + 1);
        }
    }
}

//! Bytes of the hand-off at width W (aggregationScratchBytes adds the two passes' counters).
size_t handOffBytes(int W, int D) { return (size_t)2 * 3 * W * (D / 2 + 1) * sizeof(unsigned); }
int stripCount(int W, int ndir)
{
    return cv::cudev::divUp(W, ndir == 3 ? STRIP_WARPS - 2 * (CHUNK_ROWS - 1) : COLUMN_WARPS);
}

template <typename Kernel> int residentBlocks(Kernel kernel, int threads, size_t smemBytes)
{
    int device = 0, sms = 0, perSm = 0;
    CV_CUDEV_SAFE_CALL(cudaGetDevice(&device));
    CV_CUDEV_SAFE_CALL(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
    CV_CUDEV_SAFE_CALL(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&perSm, kernel, threads, smemBytes));
    CV_Assert(perSm > 0);
    return sms * perSm;
}

template <int PPT, int NDIR, typename T>
void verticalPass(const PathInputs<T>& in, PtrStepSz<ushort> sum, int dy, HandOff h, cudaStream_t stream)
{
    const int G = PPT % 2 == 0 ? 2 : 1;
    const int W = in.censusL.cols, H = in.censusL.rows;
    const int warps = NDIR == 3 ? STRIP_WARPS : COLUMN_WARPS, R = NDIR == 3 ? CHUNK_ROWS : H;
    const size_t smemBytes = ((NDIR == 3 ? (size_t)4 * warps * (in.D / 2 + 1) : 0) + (size_t)warps * SUM_AHEAD * (in.D / 2)) *
                             sizeof(unsigned);
    const auto kernel = verticalKernel<PPT, G, NDIR, T>;
    if (smemBytes > 48 * 1024)   // above 48 KB it must be asked for (256 disparities), per device
        CV_CUDEV_SAFE_CALL(cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, (int)smemBytes));
    const int items = stripCount(W, NDIR) * cv::cudev::divUp(H, R);
    const int grid = std::min(items, residentBlocks(kernel, 32 * warps, smemBytes));
    kernel<<<grid, 32 * warps, smemBytes, stream>>>(in, sum, dy, R, h);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

template <int PPT, typename T>
void run(const PathInputs<T>& in, int numPaths, PtrStepSz<ushort> sum, uchar* scratch, cudaStream_t stream)
{
    const int G = PPT % 2 == 0 ? 2 : 1;
    const int W = in.censusL.cols, H = in.censusL.rows, D = in.D;
    const int ndir = numPaths == 8 ? 3 : 1, strips = stripCount(W, ndir);
    unsigned* costs = (unsigned*)scratch;
    int* minima = (int*)(costs + (size_t)2 * 3 * W * (D / 2));
    int* counters = minima + 2 * 3 * W;   // per pass: strips done, then the ticket
    CV_CUDEV_SAFE_CALL(cudaMemsetAsync(counters, 0, 2 * (strips + 1) * sizeof(int), stream));
    horizontalKernel<PPT, G, T><<<cv::cudev::divUp(H, ROWS_PER_BLOCK / 2), 32 * ROWS_PER_BLOCK, 0, stream>>>(in, sum);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    for (int pass = 0; pass < 2; pass++)
    {
        const HandOff h = { costs, minima, counters + pass * (strips + 1), counters + pass * (strips + 1) + strips };
        if (ndir == 3)
            verticalPass<PPT, 3>(in, sum, pass == 0 ? 1 : -1, h, stream);
        else
            verticalPass<PPT, 1>(in, sum, pass == 0 ? 1 : -1, h, stream);
    }
}

template <typename T>
void aggregate(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
               const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum,
               uchar* scratch, cudaStream_t stream)
{
    PathInputs<T> in;
    in.censusL = censusL;
    in.censusR = censusR;
    in.prior16 = prior16;
    in.own16 = scan ? own16 : PtrStepSz<short>();
    in.image = image;
    in.w = p.w;
    in.wCopy = p.wCopy;
    in.minD = p.minDisparity;
    in.D = p.numDisparities;
    in.edges = p.edgeThreshold > 0;
    // jumpPenalty's threshold made "never" (not 0) when the edge rule is off: the same penalty, one select a step.
    in.edgeThreshold = in.edges ? p.edgeThreshold : INT_MAX;
    in.scan = scan;
    switch ((p.numDisparities + 63) / 64)
    {
    case 1: run<1>(in, p.numPaths, sum, scratch, stream); break;
    case 2: run<2>(in, p.numPaths, sum, scratch, stream); break;
    case 3: run<3>(in, p.numPaths, sum, scratch, stream); break;
    default: run<4>(in, p.numPaths, sum, scratch, stream); break;
    }
}

} // namespace

size_t aggregationScratchBytes(const PipelineParams& p, int width)
{
    const int strips = stripCount(width, p.numPaths == 8 ? 3 : 1);
    return handOffBytes(width, p.numDisparities) + 2 * (strips + 1) * sizeof(int);
}

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<uchar> left,
                    const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum,
                    uchar* scratch, cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, own16, scan, sum, scratch, stream);
}

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<ushort> left,
                    const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum,
                    uchar* scratch, cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, own16, scan, sum, scratch, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
