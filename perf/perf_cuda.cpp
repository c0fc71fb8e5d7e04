// This file is part of the lidarsgm module (an OpenCV extra module).
// CUDA path on KITTI frame 000002 (inputs and output on the GPU), against cv::cuda::StereoSGM in the same process.
// Skipped where no CUDA device exists.
#include "perf_precomp.hpp"
#include "opencv2/core/cuda.hpp"
#ifdef HAVE_OPENCV_CUDASTEREO
#include "opencv2/cudastereo.hpp"
#endif

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;

static void requireDevice()
{
#ifndef HAVE_CUDA
    throw SkipTestException("built without CUDA");
#else
    if (cv::cuda::getCudaEnabledDeviceCount() <= 0)
        throw SkipTestException("no CUDA device");
#endif
}

//! KITTI frame 000002 on the GPU, at its own size or scaled (LiDAR disparities scaled with the width).
static void kittiOnGpu(cuda::GpuMat& l, cuda::GpuMat& r, cuda::GpuMat& s, Size size = Size())
{
    const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(cvtest::findDataDirectory("kitti"), "000002");
    Mat left = f.left, right = f.right, sparse = f.sparse;
    if (size.area() > 0 && size != left.size())
    {
        const double sx = (double)size.width / left.cols;
        resize(left, left, size, 0, 0, INTER_LINEAR);
        resize(right, right, size, 0, 0, INTER_LINEAR);
        resize(sparse, sparse, size, 0, 0, INTER_NEAREST);
        sparse *= sx;
    }
    l.upload(left);
    r.upload(right);
    s.upload(sparse);
}

//! One call on the stream, waited for.
static void computeOnStream(const Ptr<StereoLidarSGM>& m, const cuda::GpuMat& l, const cuda::GpuMat& r,
                            const cuda::GpuMat& s, cuda::GpuMat& d, cuda::Stream& stream)
{
    m->compute(l, r, s, d, stream);
    stream.waitForCompletion();
}

CV_ENUM(CudaFusionMode, StereoLidarSGM::MODE_SGM, StereoLidarSGM::MODE_DSGM, StereoLidarSGM::MODE_SDSGM)
typedef perf::TestBaseWithParam<tuple<Size, CudaFusionMode, int, int> > Lidarsgm_KITTI_CUDA;

// KITTI size and 1080p (the KITTI frame scaled), every mode, 4/8 paths, 128/256 disparities.
PERF_TEST_P(Lidarsgm_KITTI_CUDA, compute,
            testing::Combine(testing::Values(Size(1242, 375), Size(1920, 1080)), CudaFusionMode::all(),
                             testing::Values(4, 8), testing::Values(128, 256)))
{
    requireDevice();
    cuda::GpuMat l, r, s, d;
    kittiOnGpu(l, r, s, get<0>(GetParam()));
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, get<3>(GetParam()), 10, 120, 5, 160, 0.7, get<1>(GetParam()));
    m->setNumPaths(get<2>(GetParam()));
    cuda::Stream stream;
    computeOnStream(m, l, r, s, d, stream);   // buffers made outside the timed loop
    TEST_CYCLE() computeOnStream(m, l, r, s, d, stream);
    SANITY_CHECK_NOTHING();
}

typedef perf::TestBaseWithParam<tuple<Size, int, int> > Lidarsgm_KITTI_CUDA_Windows;

// SDSGM with the disparity windows (searchWindow margin; 0: the full range), 4/8 paths, KITTI size with 128 disparities
// and 1080p with 256.
PERF_TEST_P(Lidarsgm_KITTI_CUDA_Windows, compute,
            testing::Combine(testing::Values(Size(1242, 375), Size(1920, 1080)), testing::Values(4, 8),
                             testing::Values(0, 4)))
{
    requireDevice();
    cuda::GpuMat l, r, s, d;
    const Size size = get<0>(GetParam());
    kittiOnGpu(l, r, s, size);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, size.width > 1242 ? 256 : 128);
    m->setNumPaths(get<1>(GetParam()));
    m->setSearchWindow(get<2>(GetParam()));
    cuda::Stream stream;
    computeOnStream(m, l, r, s, d, stream);   // buffers made outside the timed loop
    TEST_CYCLE() computeOnStream(m, l, r, s, d, stream);
    SANITY_CHECK_NOTHING();
}

#ifdef HAVE_OPENCV_CUDASTEREO
typedef perf::TestBaseWithParam<int> Lidarsgm_KITTI_CUDA_Anchor;
PERF_TEST_P(Lidarsgm_KITTI_CUDA_Anchor, opencv_cuda_StereoSGM_128, testing::Values(4, 8))
{
    requireDevice();
    cuda::GpuMat l, r, s, d;
    kittiOnGpu(l, r, s);
    Ptr<cuda::StereoSGM> sgm = cuda::createStereoSGM(0, 128, 10, 120, 5,
                                                      GetParam() == 8 ? cuda::StereoSGM::MODE_HH : cuda::StereoSGM::MODE_HH4);
    cuda::Stream stream;
    sgm->compute(l, r, d, stream);
    stream.waitForCompletion();
    TEST_CYCLE()
    {
        sgm->compute(l, r, d, stream);
        stream.waitForCompletion();
    }
    SANITY_CHECK_NOTHING();
}
#endif

}} // namespace
