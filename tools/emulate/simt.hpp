// SIMT emulation on the CPU for the tools that check a CUDA kernel's rewrite where no GPU is at hand
// (tools/emulate/*.cpp, tools/emulate_kernel.sh): the CUDA qualifiers as plain C++, and the warp
// intrinsics and atomics the kernels use. A warp's 32 lanes are threads that meet at every warp intrinsic (shuffles,
// reductions, votes, __syncwarp); a block's threads meet at __syncthreads; the blocks run one after another (launch).
// It measures nothing about speed.
#ifndef LIDARSGM_TOOLS_EMULATE_SIMT_HPP
#define LIDARSGM_TOOLS_EMULATE_SIMT_HPP
#include <cuda_runtime.h>
#include <barrier>
#include <thread>
#include <vector>
#include <random>
#include <cstring>
#include <cstdio>
#include <cstdint>
#include <cassert>
#include <climits>
#include <algorithm>
#undef __device__
#undef __host__
#undef __forceinline__
#undef __global__
#undef __launch_bounds__
#undef __shared__
#undef __align__
#define __device__
#define __host__
#define __forceinline__ inline
#define __global__
#define __launch_bounds__(...)
#define __shared__ static
#define __align__(n) __attribute__((aligned(n)))

thread_local uint3 threadIdx, blockIdx;
dim3 gridDim, blockDim;
struct WarpSync { std::barrier<> bar{32}; unsigned long long slot[32]; };
thread_local WarpSync* tw;
thread_local int tlane;
std::barrier<>* blockBar;

// Every lane publishes v, then reads what it needs of the lanes' values (lane i's value: at(i)) once all have.
template <class T, class Read> T exchange(T v, Read read)
{
    std::memcpy(&tw->slot[tlane], &v, sizeof(T));
    tw->bar.arrive_and_wait();
    const auto at = [](int i) { T u; std::memcpy(&u, &tw->slot[i], sizeof(T)); return u; };
    const T r = read(at);
    tw->bar.arrive_and_wait();   // no lane publishes again before every lane has read
    return r;
}
template <class T> T __shfl_sync(unsigned, T v, int src, int width = 32)
{
    return exchange(v, [&](auto at) { return at((tlane & ~(width - 1)) | (src & (width - 1))); });
}
template <class T> T __shfl_up_sync(unsigned, T v, unsigned d, int width = 32)
{
    return exchange(v, [&](auto at) { return (tlane & (width - 1)) >= (int)d ? at(tlane - (int)d) : at(tlane); });
}
template <class T> T __shfl_xor_sync(unsigned, T v, int m, int width = 32)
{
    const int s = tlane ^ m;
    return exchange(v, [&](auto at) { return at((s & ~(width - 1)) == (tlane & ~(width - 1)) ? s : tlane); });
}
template <class T, class F> T reduceAll(unsigned mask, T v, F f)
{
    assert(mask == 0xFFFFFFFFu);   // the walk reduces over the whole warp only
    return exchange(v, [&](auto at) {
        T r = at(0);
        for (int i = 1; i < 32; i++) r = f(r, at(i));
        return r;
    });
}
const auto lesser = [](auto a, auto b) { return std::min(a, b); };
const auto greater = [](auto a, auto b) { return std::max(a, b); };
int __reduce_min_sync(unsigned m, int v) { return reduceAll(m, v, lesser); }
unsigned __reduce_min_sync(unsigned m, unsigned v) { return reduceAll(m, v, lesser); }
int __reduce_max_sync(unsigned m, int v) { return reduceAll(m, v, greater); }
unsigned __reduce_max_sync(unsigned m, unsigned v) { return reduceAll(m, v, greater); }
int __any_sync(unsigned m, int p) { return reduceAll(m, p ? 1 : 0, [](int a, int b) { return a | b; }); }
int __all_sync(unsigned m, int p) { return reduceAll(m, p ? 1 : 0, [](int a, int b) { return a & b; }); }
unsigned __ballot_sync(unsigned m, int p)
{
    return reduceAll(m, p ? 1u << tlane : 0u, [](unsigned a, unsigned b) { return a | b; });
}
int __ffs(unsigned v) { return v ? __builtin_ctz(v) + 1 : 0; }
int __popc(unsigned v) { return __builtin_popcount(v); }
void __syncwarp(unsigned = 0xFFFFFFFFu) { tw->bar.arrive_and_wait(); }
void __syncthreads() { blockBar->arrive_and_wait(); }
int blockVote;
//! Whether p holds for any thread of the block: every thread votes, all read, then the first resets the vote.
int __syncthreads_or(int p)
{
    if (p) __atomic_store_n(&blockVote, 1, __ATOMIC_RELAXED);
    blockBar->arrive_and_wait();
    const int r = __atomic_load_n(&blockVote, __ATOMIC_RELAXED);
    blockBar->arrive_and_wait();
    if (threadIdx.x == 0 && threadIdx.y == 0 && threadIdx.z == 0) __atomic_store_n(&blockVote, 0, __ATOMIC_RELAXED);
    blockBar->arrive_and_wait();
    return r;
}
unsigned __byte_perm(unsigned x, unsigned y, unsigned s)
{
    const unsigned long long v = (unsigned long long)y << 32 | x;
    unsigned r = 0;
    for (int i = 0; i < 4; i++) r |= (unsigned)(v >> (8 * ((s >> (4 * i)) & 7)) & 0xFF) << (8 * i);
    return r;
}
unsigned __vminu2(unsigned a, unsigned b)
{
    return std::min(a & 0xFFFF, b & 0xFFFF) | std::min(a >> 16, b >> 16) << 16;
}
int atomicAdd(int* a, int v) { return __atomic_fetch_add(a, v, __ATOMIC_RELAXED); }
unsigned atomicAdd(unsigned* a, unsigned v) { return __atomic_fetch_add(a, v, __ATOMIC_RELAXED); }
unsigned long long atomicAdd(unsigned long long* a, unsigned long long v)
{
    if ((uintptr_t)a & 7) { fprintf(stderr, "misaligned 64-bit atomic\n"); abort(); }
    return __atomic_fetch_add(a, v, __ATOMIC_RELAXED);
}
int min(int a, int b) { return a < b ? a : b; }
unsigned min(unsigned a, unsigned b) { return a < b ? a : b; }
int max(int a, int b) { return a > b ? a : b; }
unsigned __umulhi(unsigned a, unsigned b) { return (unsigned)((unsigned long long)a * b >> 32); }
int atomicMax(int* a, int v)
{
    int old = __atomic_load_n(a, __ATOMIC_RELAXED);
    while (v > old && !__atomic_compare_exchange_n(a, &old, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
    {
    }
    return old;
}
unsigned atomicMin(unsigned* a, unsigned v)
{
    unsigned old = __atomic_load_n(a, __ATOMIC_RELAXED);
    while (v < old && !__atomic_compare_exchange_n(a, &old, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
    {
    }
    return old;
}

// Runs kernel k over the grid: blocks one at a time, of `block` threads (a whole number of warps, x fastest).
template <class K> void launch(dim3 grid, dim3 block, K k)
{
    gridDim = grid; blockDim = block;
    const int threads = (int)(block.x * block.y * block.z);
    assert(threads % 32 == 0);
    for (unsigned by = 0; by < grid.y; by++)
        for (unsigned bx = 0; bx < grid.x; bx++)
        {
            std::barrier<> bb(threads);
            blockBar = &bb;
            std::vector<WarpSync> ws(threads / 32);
            std::vector<std::thread> th;
            for (int t = 0; t < threads; t++)
                th.emplace_back([&, t]() {
                    threadIdx = make_uint3(t % block.x, t / block.x % block.y, t / (block.x * block.y));
                    blockIdx = make_uint3(bx, by, 0);
                    tw = &ws[t / 32]; tlane = t % 32;
                    k();
                });
            for (auto& x : th) x.join();
        }
}
//! The same with blocks of `warps` warps in x.
template <class K> void launch(dim3 grid, int warps, K k) { launch(grid, dim3(32 * warps), k); }

#endif
