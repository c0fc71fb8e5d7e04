// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform rows (census.dispatch.cpp), compiled once per instruction set: censusString (pipeline.hpp) of
// each pixel, a vector of pixels at a time on rows padded by the clamped border.

#include "cpu_stages.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void censusRows(const Mat& image, Mat& census, const Range& rows);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

namespace {

//! Pixel at offset (dx, dy) of the current pixel, through rows padded by CENSUS_WIDTH / 2 clamped columns.
template <typename T>
struct PaddedWindow
{
    const T* const* rows;   //!< rows y - ry .. y + ry, clamped; column x at rows[k][x + rx]
    int x;
    T operator()(int dx, int dy) const { return rows[CENSUS_HEIGHT / 2 + dy][x + CENSUS_WIDTH / 2 + dx]; }
};

#if (CV_SIMD || CV_SIMD_SCALABLE)
inline v_uint32 load32(const uchar* p) { return vx_load_expand_q(p); }
inline v_uint32 load32(const ushort* p) { return vx_load_expand(p); }
#endif

template <typename T>
void rows(const Mat& img, Mat& census, const Range& r)
{
    const int W = img.cols, H = img.rows, rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    AutoBuffer<T> padBuf((size_t)CENSUS_HEIGHT * (W + 2 * rx));
    const T* padded[CENSUS_HEIGHT];
    for (int y = r.start; y < r.end; y++)
    {
        for (int k = 0; k < CENSUS_HEIGHT; k++)
        {
            const T* src = img.ptr<T>(std::min(std::max(y + k - ry, 0), H - 1));
            T* dst = padBuf.data() + (size_t)k * (W + 2 * rx);
            for (int i = 0; i < W + 2 * rx; i++)
                dst[i] = src[std::min(std::max(i - rx, 0), W - 1)];
            padded[k] = dst;
        }
        unsigned* out = census.ptr<unsigned>(y);
        int x = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        const int n = VTraits<v_uint32>::vlanes();
        const v_uint32 one = vx_setall_u32(1);
        for (; x <= W - n; x += n)
        {
            // The bits of censusString, a lane per pixel, in the same order.
            v_uint32 c = vx_setzero_u32();
            for (int dy = -ry; dy <= 0; dy++)
            {
                const int dxEnd = dy < 0 ? rx : -1;
                for (int dx = -rx; dx <= dxEnd; dx++)
                {
                    const v_uint32 a = load32(padded[ry + dy] + x + rx + dx);
                    const v_uint32 b = load32(padded[ry - dy] + x + rx - dx);
                    c = v_or(v_shl<1>(c), v_and(v_gt(a, b), one));
                }
            }
            v_store(out + x, c);
        }
#endif
        PaddedWindow<T> at = { padded, x };
        for (; at.x < W; at.x++)
            out[at.x] = censusString(at);
    }
}

} // namespace

void censusRows(const Mat& image, Mat& census, const Range& r)
{
    if (image.depth() == CV_8U)
        rows<uchar>(image, census, r);
    else
        rows<ushort>(image, census, r);
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
