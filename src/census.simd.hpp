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

/** How the padded rows hold pixels: 8-bit pixels with the top bit flipped, so that signed byte compares order them
as unsigned ones do (vector units compare signed bytes in one instruction); 16-bit pixels as they are. Only
comparisons read them (censusString), so the strings are the same. */
template <typename T> struct Stored { typedef T type; static T put(T v) { return v; } };
template <> struct Stored<uchar> { typedef schar type; static schar put(uchar v) { return (schar)(v ^ 0x80); } };

#if (CV_SIMD || CV_SIMD_SCALABLE)
inline v_uint16 load16(const ushort* p) { return vx_load(p); }

/** The strings of a row of a 16-bit image from pixel x on, in whole vectors of pixels; returns the first pixel left
for the scalar tail. The bits of censusString in 16-bit lanes, the first CENSUS_BITS - 16 pairs in the high half, the
last 16 in the low half, joined into 32-bit strings at the end. */
inline int censusVectors(const ushort* const* padded, int x, int W, unsigned* out)
{
    const int rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
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
    return x;
}

/** The same for 8-bit images, a byte lane per pixel (twice the pixels per instruction): bit b of the string goes to
byte b / 8, each byte shifting its bits in (h + h - (a > b), the compare giving -1), and the four bytes of a pixel are
interleaved into its 32-bit string at the end. */
inline int censusVectors(const schar* const* padded, int x, int W, unsigned* out)
{
    const int rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    const int n = VTraits<v_int8>::vlanes(), n32 = VTraits<v_uint32>::vlanes();
    for (; x <= W - n; x += n)
    {
        v_uint8 b0 = vx_setzero_u8(), b1 = vx_setzero_u8(), b2 = vx_setzero_u8(), b3 = vx_setzero_u8();
        int bit = CENSUS_BITS - 1;
        for (int dy = -ry; dy <= 0; dy++)
        {
            const int dxEnd = dy < 0 ? rx : -1;
            for (int dx = -rx; dx <= dxEnd; dx++, bit--)
            {
                const v_uint8 gt = v_reinterpret_as_u8(v_gt(vx_load(padded[ry + dy] + x + rx + dx),
                                                            vx_load(padded[ry - dy] + x + rx - dx)));
                v_uint8& h = bit >= 24 ? b3 : bit >= 16 ? b2 : bit >= 8 ? b1 : b0;
                h = v_sub_wrap(v_add_wrap(h, h), gt);
            }
        }
        v_uint8 z0, z1, w0, w1;
        v_zip(b0, b1, z0, z1);   // pixel i: b0 | b1 << 8
        v_zip(b2, b3, w0, w1);   // pixel i: b2 | b3 << 8
        v_uint16 o0, o1, o2, o3;
        v_zip(v_reinterpret_as_u16(z0), v_reinterpret_as_u16(w0), o0, o1);
        v_zip(v_reinterpret_as_u16(z1), v_reinterpret_as_u16(w1), o2, o3);
        v_store(out + x, v_reinterpret_as_u32(o0));
        v_store(out + x + n32, v_reinterpret_as_u32(o1));
        v_store(out + x + 2 * n32, v_reinterpret_as_u32(o2));
        v_store(out + x + 3 * n32, v_reinterpret_as_u32(o3));
    }
    return x;
}
#endif

template <typename T>
void rows(const Mat& img, Mat& census, const Range& r)
{
    typedef typename Stored<T>::type S;
    const int W = img.cols, H = img.rows, rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    // Rows r.start - ry .. r.end - 1 + ry, clamped, each padded by rx clamped columns once.
    const int n = r.end - r.start + 2 * ry, pw = W + 2 * rx;
    AutoBuffer<S> padBuf((size_t)n * pw);
    for (int k = 0; k < n; k++)
    {
        const T* src = img.ptr<T>(std::min(std::max(r.start - ry + k, 0), H - 1));
        S* dst = padBuf.data() + (size_t)k * pw;
        for (int i = 0; i < rx; i++)
        {
            dst[i] = Stored<T>::put(src[0]);
            dst[pw - 1 - i] = Stored<T>::put(src[W - 1]);
        }
        for (int i = 0; i < W; i++)
            dst[rx + i] = Stored<T>::put(src[i]);
    }
    const S* padded[CENSUS_HEIGHT];
    for (int y = r.start; y < r.end; y++)
    {
        for (int k = 0; k < CENSUS_HEIGHT; k++)
            padded[k] = padBuf.data() + (size_t)(y - r.start + k) * pw;
        unsigned* out = census.ptr<unsigned>(y);
        int x = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        x = censusVectors(padded, x, W, out);
#endif
        PaddedWindow<S> at = { padded, x };
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
