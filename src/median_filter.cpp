// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// 3x3 median of the disparity maps after the winner-takes-all, before the consistency check (the step the paper's
// public code takes and its text leaves out). It removes isolated wrong disparities, and isolated holes close when
// most neighbours agree. "No disparity" ranks above every value and the border is clamped (pipeline.hpp).

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace {

#if (CV_SIMD || CV_SIMD_SCALABLE)
struct VectorMinMax
{
    static v_int16 lo(const v_int16& a, const v_int16& b) { return v_min(a, b); }
    static v_int16 hi(const v_int16& a, const v_int16& b) { return v_max(a, b); }
};
#endif

void medianRows(const Mat& src, Mat& dst, const Range& rows)
{
    const int W = src.cols, H = src.rows;
    // Sorted columns of the window, with one clamped column on each side: lo[i + 1] is column i.
    AutoBuffer<short> buf(3 * (W + 2));
    short* lo = buf.data();
    short* mi = lo + W + 2;
    short* hi = mi + W + 2;
    for (int y = rows.start; y < rows.end; y++)
    {
        const short* a = src.ptr<short>(std::max(y - 1, 0));
        const short* b = src.ptr<short>(y);
        const short* c = src.ptr<short>(std::min(y + 1, H - 1));
        short* out = dst.ptr<short>(y);
        int x = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        const int n = VTraits<v_int16>::vlanes();
        const v_int16 vnone = vx_setall_s16(NO_DISP), vmax = vx_setall_s16(SHRT_MAX);
        for (; x <= W - n; x += n)
        {
            v_int16 va = vx_load(a + x), vb = vx_load(b + x), vc = vx_load(c + x);
            va = v_select(v_eq(va, vnone), vmax, va);
            vb = v_select(v_eq(vb, vnone), vmax, vb);
            vc = v_select(v_eq(vc, vnone), vmax, vc);
            sortColumn3<VectorMinMax>(va, vb, vc);
            v_store(lo + 1 + x, va);
            v_store(mi + 1 + x, vb);
            v_store(hi + 1 + x, vc);
        }
#endif
        for (; x < W; x++)
        {
            int ka = medianKey(a[x]), kb = medianKey(b[x]), kc = medianKey(c[x]);
            sortColumn3<ScalarMinMax>(ka, kb, kc);
            lo[1 + x] = (short)ka;
            mi[1 + x] = (short)kb;
            hi[1 + x] = (short)kc;
        }
        lo[0] = lo[1]; mi[0] = mi[1]; hi[0] = hi[1];
        lo[W + 1] = lo[W]; mi[W + 1] = mi[W]; hi[W + 1] = hi[W];

        x = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        for (; x <= W - n; x += n)
        {
            const v_int16 k = medianOfColumns<VectorMinMax>(
                vx_load(lo + x), vx_load(lo + x + 1), vx_load(lo + x + 2),
                vx_load(mi + x), vx_load(mi + x + 1), vx_load(mi + x + 2),
                vx_load(hi + x), vx_load(hi + x + 1), vx_load(hi + x + 2));
            v_store(out + x, v_select(v_eq(k, vmax), vnone, k));
        }
#endif
        for (; x < W; x++)
            out[x] = (short)medianValue(medianOfColumns<ScalarMinMax>(lo[x], lo[x + 1], lo[x + 2], mi[x], mi[x + 1],
                                                                     mi[x + 2], hi[x], hi[x + 1], hi[x + 2]));
    }
}

} // namespace

void medianFilter(const Mat& src, Mat& dst)
{
    CV_Assert(src.type() == CV_16SC1 && src.data != dst.data);
    dst.create(src.size(), CV_16SC1);
    parallel_for_(Range(0, src.rows), [&](const Range& r) { medianRows(src, dst, r); },
                  rowStripes(src.rows));
}

}}} // namespace cv::lidarsgm::detail
