// Cost of the row-by-row hand-off that a strip-wise SGM sweep needs on the GPU (doc/design.md, "CUDA aggregation").
//
// A sweep that computes the vertical and both diagonal directions of a pixel together keeps a column strip per block;
// the diagonals at a strip's edges need the neighbouring strips' path costs of the previous row, so every block waits
// for both neighbours to finish row y - 1 before it finishes row y. This program times that chain alone: one block per
// strip, launched cooperatively (all resident), each row: wait for both neighbours' progress flags, read their edge
// vectors (D 16-bit costs each), spin `work` dependent multiply-adds per thread (standing in for the row's path
// arithmetic), write its own edge vectors, fence, publish its progress. With work 0 the time per row is the hand-off
// latency; the output table gives it per strip count and row count, to set against the whole path kernel's time.
//   nvcc -O3 -arch=sm_90 tools/analysis/wavefront_handoff.cu -o wavefront_handoff && ./wavefront_handoff

#include <cstdio>
#include <cstdlib>
#include <vector>
#include <algorithm>
#include <cuda_runtime.h>

#define CHECK(call) do { cudaError_t e = (call); if (e != cudaSuccess) { \
    std::printf("CUDA error %s at %s:%d\n", cudaGetErrorString(e), __FILE__, __LINE__); std::exit(1); } } while (0)

__device__ __forceinline__ int loadAcquire(const int* p)
{
    int v;
    asm volatile("ld.acquire.gpu.global.s32 %0, [%1];" : "=r"(v) : "l"(p) : "memory");
    return v;
}

__device__ __forceinline__ void storeRelease(int* p, int v)
{
    asm volatile("st.release.gpu.global.s32 [%0], %1;" :: "l"(p), "r"(v) : "memory");
}

// edges: [strip][row parity][side 0 = left edge, 1 = right edge][D / 8] uint4 (D 16-bit costs).
__global__ void sweep(int H, int work, int vecs, int* progress, uint4* edges, unsigned* sink)
{
    const int s = blockIdx.x, nS = gridDim.x, t = threadIdx.x;
    unsigned acc = t;
    for (int y = 0; y < H; y++)
    {
        if (t == 0)
        {
            if (s > 0)
                while (loadAcquire(progress + s - 1) < y) {}
            if (s + 1 < nS)
                while (loadAcquire(progress + s + 1) < y) {}
        }
        __syncthreads();
        // The neighbours' facing edges of row y - 1 (L2: __ldcg, no stale L1 line).
        const int par = (y + 1) & 1;
        if (y > 0 && t < vecs)
        {
            if (s > 0)
                acc += __ldcg(edges + ((size_t)((s - 1) * 2 + par) * 2 + 1) * vecs + t).x;
            if (s + 1 < nS)
                acc += __ldcg(edges + ((size_t)((s + 1) * 2 + par) * 2 + 0) * vecs + t).y;
        }
        for (int i = 0; i < work; i++)
            acc = acc * 1664525u + 1013904223u;
        if (t < vecs)
        {
            const uint4 v = make_uint4(acc, acc + 1, acc + 2, acc + 3);
            edges[((size_t)(s * 2 + (y & 1)) * 2 + 0) * vecs + t] = v;
            edges[((size_t)(s * 2 + (y & 1)) * 2 + 1) * vecs + t] = v;
        }
        __threadfence();
        __syncthreads();
        if (t == 0)
            storeRelease(progress + s, y + 1);
    }
    if (acc == 0x12345678u)
        sink[0] = acc;
}

int main()
{
    cudaDeviceProp prop;
    CHECK(cudaGetDeviceProperties(&prop, 0));
    std::printf("%s, %d SMs\n", prop.name, prop.multiProcessorCount);
    const int threads = 256, maxStrips = 1024, D = 256, vecs = D / 8;
    int perSM = 0;
    CHECK(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&perSM, sweep, threads, 0));
    int* progress;
    uint4* edges;
    unsigned* sink;
    CHECK(cudaMalloc(&progress, maxStrips * sizeof(int)));
    CHECK(cudaMalloc(&edges, (size_t)maxStrips * 4 * vecs * sizeof(uint4)));
    CHECK(cudaMalloc(&sink, sizeof(unsigned)));
    cudaEvent_t a, b;
    CHECK(cudaEventCreate(&a));
    CHECK(cudaEventCreate(&b));
    std::printf("| strips | rows | work per row (MADs per thread) | median ms (20 runs) | us per row |\n");
    const int stripsList[] = { 39, 78, 120, 155, 240, 480 };
    const int rowsList[] = { 375, 1080, 2160 };
    const int workList[] = { 0, 200, 800 };
    for (int nS : stripsList)
    {
        if (nS > perSM * prop.multiProcessorCount)
            continue;
        for (int H : rowsList)
            for (int work : workList)
            {
                int Hh = H, w = work;
                void* args[] = { &Hh, &w, (void*)&vecs, &progress, &edges, &sink };
                std::vector<float> ms;
                for (int r = 0; r < 22; r++)
                {
                    CHECK(cudaMemset(progress, 0, maxStrips * sizeof(int)));
                    CHECK(cudaEventRecord(a));
                    CHECK(cudaLaunchCooperativeKernel((void*)sweep, dim3(nS), dim3(threads), args, 0, 0));
                    CHECK(cudaEventRecord(b));
                    CHECK(cudaEventSynchronize(b));
                    float t;
                    CHECK(cudaEventElapsedTime(&t, a, b));
                    if (r >= 2)
                        ms.push_back(t);
                }
                std::sort(ms.begin(), ms.end());
                const float med = ms[ms.size() / 2];
                std::printf("| %d | %d | %d | %.3f | %.2f |\n", nS, H, work, med, 1000.0f * med / H);
            }
    }
    return 0;
}
