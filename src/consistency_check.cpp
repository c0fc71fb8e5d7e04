// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Stereo-LiDAR consistency check (paper Sec. IV-C, Eq. 6). The LiDAR view uses the original sparse map, not the
// semidense one: propagated values need not obey the sensors' geometry (the paper's note under Eq. 6).

#include "precomp.hpp"
#include "pipeline.hpp"
#include "sparse_window.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void consistencyCheck(Mat& disp16, const Mat& dispInt, const Mat& dispRight, const Mat& sparse16,
                      const PipelineParams& p)
{
    typedef StereoLidarSGM S;
    if (p.check == S::CHECK_NONE)
        return;
    const int W = disp16.cols, H = disp16.rows;
    const bool useStereo = p.check == S::CHECK_STEREO || p.check == S::CHECK_STEREO_LIDAR;
    const bool useLidar = p.check == S::CHECK_CAMERA_LIDAR || p.check == S::CHECK_STEREO_LIDAR;
    CV_Assert(!useLidar || (sparse16.type() == CV_16SC1 && sparse16.size() == disp16.size()));
    const SparseColumns cols(useLidar ? sparse16 : Mat(1, 1, CV_16SC1, Scalar::all(NO_DISP)));
    const int rc = p.checkRadius, tc = p.checkThreshold16;

    parallel_for_(Range(0, H), [&](const Range& r) {
        WindowCursor cur(cols, rc, useLidar ? r.start : 0);
        for (int y = r.start; y < r.end; y++)
        {
            if (useLidar)
                cur.moveTo(y);
            short* d16 = disp16.ptr<short>(y);
            const short* di = dispInt.ptr<short>(y);
            const short* dr = dispRight.ptr<short>(y);
            for (int x = 0; x < W; x++)
            {
                if (d16[x] == NO_DISP)
                    continue;
                bool ok = false;
                if (useStereo)
                {
                    const int xr = x - di[x];
                    ok = xr >= 0 && xr < W && dr[xr] != NO_DISP && std::abs(di[x] - dr[xr]) <= p.lrMaxDiff;
                }
                if (!ok && useLidar)
                {
                    const int v = d16[x];
                    const int c0 = std::max(0, x - rc), c1 = std::min(W - 1, x + rc);
                    for (int c = c0; c <= c1 && !ok; c++)
                        for (int i = cur.lo[c]; i < cur.hi[c]; i++)
                            if (std::abs(v - cols.value[i]) <= tc)
                            {
                                ok = true;
                                break;
                            }
                }
                if (!ok)
                    d16[x] = NO_DISP;
            }
        }
    }, std::max(1, H / 16));
}

}}} // namespace cv::lidarsgm::detail
