// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Stereo-LiDAR consistency check (paper Sec. IV-C, Eq. 6), fused with the conversion to the output format. The LiDAR
// view uses the original sparse map, not the semidense one: propagated values need not obey the sensors' geometry
// (the paper's note under Eq. 6). With ring interpolation the LiDAR test includes the ring check (pipeline.hpp).
// Where asked, each output pixel's confidence (outputConfidence, pipeline.hpp) is written beside it.

#include "precomp.hpp"
#include "cpu_stages.hpp"
#include "sparse_window.hpp"
#include <memory>

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

/* confidenceValue(outputConfidence(e, r)) for every evidence e and spread r (r capped as the rule caps it): a table
lookup per pixel instead of an integer and a float division, the same values. */
struct ConfidenceTable
{
    enum { R = 2049 };
    std::vector<float> v;
    ConfidenceTable() : v(5 * R)
    {
        for (int e = 0; e <= 4; e++)
            for (int r = 0; r < R; r++)
                v[e * R + r] = confidenceValue(outputConfidence(e, r));
    }
    float operator()(int e, int r) const { return v[e * R + std::min(r, (int)R - 1)]; }
};

/* confidenceRange16 of a whole row y of disp16 at once: each row's 3-wide minima and maxima (NO_DISP left out), then
the three rows' combined; the same values as the rule's 3x3 loop, without its per-pixel bounds tests. lo, hi: scratch
of the row's width. */
inline void confidenceRangeRow(const Mat& disp16, int y, short* lo, short* hi, int* range)
{
    const int W = disp16.cols, H = disp16.rows;
    for (int x = 0; x < W; x++)
    {
        lo[x] = SHRT_MAX;
        hi[x] = SHRT_MIN;
    }
    // Branch-free, so that the compiler vectorises it: NO_DISP is SHRT_MIN, below every value, so the maxima ignore
    // it as they are; for the minima it is read as SHRT_MAX.
    const auto asLow = [](short d) { return d == NO_DISP ? (short)SHRT_MAX : d; };
    for (int v = std::max(0, y - 1); v <= std::min(H - 1, y + 1); v++)
    {
        const short* d = disp16.ptr<short>(v);
        for (int x = 0; x < W; x++)
        {
            lo[x] = std::min(lo[x], asLow(d[x]));
            hi[x] = std::max(hi[x], d[x]);
        }
        for (int x = 1; x < W; x++)
        {
            lo[x] = std::min(lo[x], asLow(d[x - 1]));
            hi[x] = std::max(hi[x], d[x - 1]);
        }
        for (int x = 0; x + 1 < W; x++)
        {
            lo[x] = std::min(lo[x], asLow(d[x + 1]));
            hi[x] = std::max(hi[x], d[x + 1]);
        }
    }
    for (int x = 0; x < W; x++)
        range[x] = hi[x] >= lo[x] ? hi[x] - lo[x] : 0;
}

/* Whether a value of cols within tc of v lies in the columns x - radius .. x + radius (of W) of the cursor's rows:
outward from x (a confirming value is likeliest near the pixel), stopping at the first (an existence test: the order
cannot change it). */
inline bool lidarValueNear(const SparseColumns& cols, const WindowCursor& cur, int radius, int x, int v, int W, int tc)
{
    for (int k = 0; k <= 2 * radius; k++)
    {
        const int c = x + ((k & 1) ? -((k + 1) >> 1) : (k >> 1));
        if (c < 0 || c >= W)
            continue;
        for (int i = cur.lo[c]; i < cur.hi[c]; i++)
            if (std::abs(v - cols.value[i]) <= tc)
                return true;
    }
    return false;
}

} // namespace

void consistencyCheck(const Mat& disp16, const Mat& dispInt, const Mat& dispRight, const Mat& sparse16,
                      const Mat& nonUnique16, const RingMaps& rings, const PipelineParams& p, OutputArray _out,
                      OutputArray _confidence, const SparseColumns* points)
{
    const int W = disp16.cols, H = disp16.rows;
    const bool useStereo = p.stereoCheck, useLidar = p.lidarCheck, conf = p.confidence;
    // The confidence's evidence runs both tests wherever it can, whatever the check keeps.
    const bool lidarTest = useLidar || (conf && !sparse16.empty());
    CV_Assert(!lidarTest || (sparse16.type() == CV_16SC1 && sparse16.size() == disp16.size()));
    const bool useRings = ringCheckOn(p) && rings.valid;
    CV_Assert(!useRings || (nonUnique16.type() == CV_16SC1 && nonUnique16.size() == disp16.size() &&
                            rings.nearest.type() == CV_16SC4 && rings.nearest.size() == disp16.size()));
    const RingNearestMap ringNearest = { useRings ? rings.nearest.ptr<Vec4s>() : nullptr,
                                         useRings ? rings.nearest.step1() / 4 : 0 };
    const size_t sparseStep = sparse16.step1();
    const auto ringSupports = [&](int v, int x, int y) {
        return ringLineSupportsOf(v, ringNearest, sparse16.ptr<short>(), sparseStep, x, y, rings.gap,
                                  p.checkThreshold16);
    };
    _out.create(disp16.size(), p.floatOutput ? CV_32FC1 : CV_16SC1);
    Mat out = _out.getMat(), confidence;
    if (conf)
    {
        _confidence.create(disp16.size(), CV_32FC1);
        confidence = _confidence.getMat();
    }
    static const ConfidenceTable confidenceOf;
    SparseColumns own;
    if (!lidarTest)
        own.build(Mat(1, 1, CV_16SC1, Scalar::all(NO_DISP)));
    else if (!points)
        own.build(sparse16);
    const SparseColumns& cols = lidarTest && points ? *points : own;
    const int rc = p.checkRadius, tc = p.checkThreshold16;

    const int rs = p.semidenseRadius;   // the confidence's LiDAR evidence window (outputConfidence)
    const auto lidarConfirms = [&](const WindowCursor& cur, int radius, int x, int v) {
        return lidarValueNear(cols, cur, radius, x, v, W, tc);
    };
    parallel_for_(Range(0, H), [&](const Range& r) {
        WindowCursor cur(cols, rc, lidarTest ? r.start : 0);
        // The evidence's window, only where the confidence is asked for (a cursor costs a search per column).
        std::unique_ptr<WindowCursor> near(conf && lidarTest ? new WindowCursor(cols, rs, r.start) : nullptr);
        AutoBuffer<short> rowBuf(3 * W);
        AutoBuffer<int> rangeBuf(conf ? W : 1);
        short* res = rowBuf.data();
        int* range16 = rangeBuf.data();
        for (int y = r.start; y < r.end; y++)
        {
            if (lidarTest)
                cur.moveTo(y);
            if (near)
                near->moveTo(y);
            const short* d16 = disp16.ptr<short>(y);
            const short* di = dispInt.ptr<short>(y);
            const short* dr = dispRight.ptr<short>(y);
            const short* nu = useRings ? nonUnique16.ptr<short>(y) : nullptr;
            float* co = conf ? confidence.ptr<float>(y) : nullptr;
            if (conf)
                confidenceRangeRow(disp16, y, res + W, res + 2 * W, range16);
            for (int x = 0; x < W; x++)
            {
                res[x] = d16[x];
                if (d16[x] == NO_DISP)
                {
                    // A non-unique winner that the ring check keeps: LiDAR evidence alone.
                    const bool rescued = nu && nu[x] != NO_DISP && ringSupports(nu[x], x, y);
                    if (rescued)
                        res[x] = nu[x];
                    if (co)
                        co[x] = rescued ? confidenceOf(checkEvidence(false, true), range16[x]) : 0.f;
                    continue;
                }
                bool lr = false, li = false, ln = false;   // left-right; LiDAR in the check's window; in rs's
                if (useStereo || conf)
                {
                    // A match outside the right image cannot be verified: it fails (the LiDAR test may keep it).
                    const int xr = x - di[x];
                    lr = xr >= 0 && xr < W && dr[xr] != NO_DISP && std::abs(di[x] - dr[xr]) <= p.lrMaxDiff;
                }
                const int v = d16[x];
                if (near)
                    ln = lidarConfirms(*near, rs, x, v);
                if (useLidar && !(useStereo && lr))
                    li = (ln && rs <= rc) || lidarConfirms(cur, rc, x, v);
                if (useRings && ((useLidar && !li && !(useStereo && lr)) || (conf && !ln)) && ringSupports(v, x, y))
                    li = ln = true;
                const bool ok = (!useStereo && !useLidar) || (useStereo && lr) || (useLidar && li);
                if (!ok)
                    res[x] = NO_DISP;
                if (co)
                    co[x] = ok ? confidenceOf(checkEvidence(lr, ln), range16[x]) : 0.f;
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
