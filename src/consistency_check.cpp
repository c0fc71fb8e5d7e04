// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Stereo-LiDAR consistency check (paper Sec. IV-C, Eq. 6), fused with the conversion to the output format. The LiDAR
// view uses the original sparse map, not the semidense one: propagated values need not obey the sensors' geometry
// (the paper's note under Eq. 6). With ring interpolation the LiDAR test includes the ring check (pipeline.hpp).

#include "precomp.hpp"
#include "cpu_stages.hpp"
#include "sparse_window.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace {

//! One row of 1/16-pixel values to the output type.
void encodeRow(const short* d16, int W, const PipelineParams& p, Mat& out, int y)
{
    if (p.floatOutput)
    {
        float* o = out.ptr<float>(y);
        for (int x = 0; x < W; x++)
            o[x] = encodeOutput32(d16[x], p.minDisparity);
    }
    else
    {
        short* o = out.ptr<short>(y);
        for (int x = 0; x < W; x++)
            o[x] = encodeOutput16(d16[x], p.minDisparity);
    }
}

} // namespace

void consistencyCheck(const Mat& disp16, const Mat& dispInt, const Mat& dispRight, const Mat& sparse16,
                      const Mat& nonUnique16, const RingMaps& rings, const PipelineParams& p, OutputArray _out)
{
    const int W = disp16.cols, H = disp16.rows;
    const bool useStereo = p.stereoCheck, useLidar = p.lidarCheck;
    CV_Assert(!useLidar || (sparse16.type() == CV_16SC1 && sparse16.size() == disp16.size()));
    const bool useRings = ringCheckOn(p) && rings.valid;
    CV_Assert(!useRings || (nonUnique16.type() == CV_16SC1 && nonUnique16.size() == disp16.size() &&
                            rings.above16.size() == disp16.size() && rings.below16.size() == disp16.size() &&
                            rings.above16.step1() == rings.below16.step1()));
    const short* above = useRings ? rings.above16.ptr<short>() : nullptr;
    const short* below = useRings ? rings.below16.ptr<short>() : nullptr;
    const size_t ringStep = useRings ? rings.above16.step1() : 0, sparseStep = sparse16.step1();
    const auto ringSupports = [&](int v, int x, int y) {
        return ringLineSupports(v, above, below, ringStep, sparse16.ptr<short>(), sparseStep, x, y, W, rings.gap,
                                p.checkThreshold16);
    };
    _out.create(disp16.size(), p.floatOutput ? CV_32FC1 : CV_16SC1);
    Mat out = _out.getMat();
    const SparseColumns cols(useLidar ? sparse16 : Mat(1, 1, CV_16SC1, Scalar::all(NO_DISP)));
    const int rc = p.checkRadius, tc = p.checkThreshold16;

    parallel_for_(Range(0, H), [&](const Range& r) {
        WindowCursor cur(cols, rc, useLidar ? r.start : 0);
        AutoBuffer<short> rowBuf(W);
        short* res = rowBuf.data();
        for (int y = r.start; y < r.end; y++)
        {
            if (useLidar)
                cur.moveTo(y);
            const short* d16 = disp16.ptr<short>(y);
            const short* di = dispInt.ptr<short>(y);
            const short* dr = dispRight.ptr<short>(y);
            const short* nu = useRings ? nonUnique16.ptr<short>(y) : nullptr;
            for (int x = 0; x < W; x++)
            {
                res[x] = d16[x];
                if (d16[x] == NO_DISP && nu && nu[x] != NO_DISP && ringSupports(nu[x], x, y))
                    res[x] = nu[x];
                if (d16[x] == NO_DISP || (!useStereo && !useLidar))
                    continue;
                bool ok = false;
                if (useStereo)
                {
                    // A match outside the right image cannot be verified: it fails (the LiDAR test may keep it).
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
                    ok = ok || (useRings && ringSupports(v, x, y));
                }
                if (!ok)
                    res[x] = NO_DISP;
            }
            encodeRow(res, W, p, out, y);
        }
    }, rowStripes(H));
}

void encodeOutput(const Mat& disp16, const PipelineParams& p, OutputArray _out)
{
    CV_Assert(disp16.type() == CV_16SC1);
    _out.create(disp16.size(), p.floatOutput ? CV_32FC1 : CV_16SC1);
    Mat out = _out.getMat();
    for (int y = 0; y < disp16.rows; y++)
        encodeRow(disp16.ptr<short>(y), disp16.cols, p, out, y);
}

}}} // namespace cv::lidarsgm::detail
