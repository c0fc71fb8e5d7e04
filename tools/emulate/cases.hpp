// What the emulated cases (tools/emulate/*.cpp) share: a case's random numbers from its seed, and census strings.
#ifndef LIDARSGM_TOOLS_EMULATE_CASES_HPP
#define LIDARSGM_TOOLS_EMULATE_CASES_HPP
#include <cstdlib>
#include <random>
#include <vector>
#include "opencv2/core/cuda_types.hpp"

//! A case's random numbers: the seed is argv[1] (1 without); U(a, b) is uniform in [a, b].
struct CaseRandom
{
    int seed;
    std::mt19937 rng;
    CaseRandom(int argc, char** argv) : seed(argc > 1 ? atoi(argv[1]) : 1), rng(seed) {}
    int operator()(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }
};

//! Random census strings of a W x H pair, the right one with `margin` columns left of its first (right[-d]).
struct RandomCensus
{
    std::vector<int> l, r;
    cv::cuda::PtrStepSz<int> left, right;
    RandomCensus(std::mt19937& rng, int W, int H, int margin) : l((size_t)W * H), r((size_t)(W + margin) * H)
    {
        for (auto& v : l) v = (int)rng();
        for (auto& v : r) v = (int)rng();
        left = cv::cuda::PtrStepSz<int>(H, W, l.data(), W * sizeof(int));
        right = cv::cuda::PtrStepSz<int>(H, W, r.data() + margin, (W + margin) * sizeof(int));
    }
};

#endif
