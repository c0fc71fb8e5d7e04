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
inline v_uint16 load16(const uchar* p) { return vx_load_expand(p); }
inline v_uint16 load16(const ushort* p) { return vx_load(p); }
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
        // The bits of censusString, a 16-bit lane per pixel: the first 15 pairs make the high half, the last 16 the
        // low half (in the string's order), joined into 32-bit strings at the end.
        const int n = VTraits<v_uint16>::vlanes(), n32 = VTraits<v_uint32>::vlanes();
        const v_uint16 one = vx_setall_u16(1);
        for (; x <= W - n; x += n)
        {
            v_uint16 half[2] = { vx_setzero_u16(), vx_setzero_u16() };
            int bit = 0;
            for (int dy = -ry; dy <= 0; dy++)
            {
                const int dxEnd = dy < 0 ? rx : -1;
                for (int dx = -rx; dx <= dxEnd; dx++, bit++)
                {
                    const v_uint16 a = load16(padded[ry + dy] + x + rx + dx);
                    const v_uint16 b = load16(padded[ry - dy] + x + rx - dx);
                    v_uint16& h = half[bit < CENSUS_BITS - 16 ? 0 : 1];
                    h = v_or(v_shl<1>(h), v_and(v_gt(a, b), one));
                }
            }
            v_uint32 lo0, lo1, hi0, hi1;
            v_expand(half[1], lo0, lo1);
            v_expand(half[0], hi0, hi1);
            v_store(out + x, v_or(v_shl<16>(hi0), lo0));
            v_store(out + x + n32, v_or(v_shl<16>(hi1), lo1));
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
