// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// LiDAR point clouds from files: PCD (PCL's format), PLY and KITTI's .bin, as N x 4 float (x, y, z, intensity).
// Parsers of untrusted files: every size is checked against the bytes there before anything is read or allocated.

#include "../precomp.hpp"
#include "opencv2/lidarsgm/datasets.hpp"
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <fstream>
#include <sstream>

namespace cv { namespace lidarsgm {

namespace {

[[noreturn]] void fail(const String& path, const std::string& what)
{
    LIDARSGM_Error(Error::StsParseError, "lidarsgm: point cloud " + path + ": " + what);
}

/* The fields a cloud has beyond x, y, z and intensity, which readPointCloud does not read (a ring or time field, say,
where the intensity would be expected): said once per folder and list, so that a recording's frames say it once.
PCL's padding fields ("_") are no news. */
void noteUnreadFields(const String& path, const std::vector<std::string>& unread)
{
    std::string list;
    int n = 0;
    for (const std::string& f : unread)
        if (f != "_")
        {
            list += (list.empty() ? "" : ", ") + f;
            n++;
        }
    if (list.empty())
        return;
    static Mutex mutex;
    static std::set<std::string> said;   // folder and list: a recording's frames share their folder
    const size_t slash = path.find_last_of("/\\");
    AutoLock lock(mutex);
    if (!said.insert((slash == String::npos ? String() : path.substr(0, slash)) + "\n" + list).second)
        return;
    lidarsgmWarning("lidarsgm: point cloud " + path + (n == 1 ? ": the field " : ": the fields ") + list +
                    (n == 1 ? " is" : " are") + " not read (readPointCloud takes x, y, z and intensity; the intensity is "
                    "0 where the file has none)");
}

std::vector<char> readFile(const String& path)
{
    std::ifstream f(path.c_str(), std::ios::binary | std::ios::ate);
    if (!f)
        LIDARSGM_Error(Error::StsObjectNotFound, "lidarsgm: cannot open point cloud " + path);
    const std::streamsize bytes = f.tellg();
    std::vector<char> data((size_t)std::max<std::streamsize>(bytes, 0));
    f.seekg(0);
    if (bytes > 0 && !f.read(data.data(), bytes))
        LIDARSGM_Error(Error::StsParseError, "lidarsgm: cannot read point cloud " + path);
    return data;
}

//! A scalar field of a record: its type (F float, I signed, U unsigned), its size in bytes, its big-endian order.
struct Scalar
{
    char type = 'F';
    int size = 4;
    bool bigEndian = false;

    double read(const unsigned char* p) const
    {
        unsigned char b[8];
        for (int i = 0; i < size; i++)
            b[i] = p[bigEndian ? size - 1 - i : i];   // the host is little-endian (OpenCV's supported platforms)
        switch (type * 16 + size)
        {
        case 'F' * 16 + 4: { float v; std::memcpy(&v, b, 4); return v; }
        case 'F' * 16 + 8: { double v; std::memcpy(&v, b, 8); return v; }
        case 'I' * 16 + 1: return (double)(int8_t)b[0];
        case 'I' * 16 + 2: { int16_t v; std::memcpy(&v, b, 2); return v; }
        case 'I' * 16 + 4: { int32_t v; std::memcpy(&v, b, 4); return v; }
        case 'I' * 16 + 8: { int64_t v; std::memcpy(&v, b, 8); return (double)v; }
        case 'U' * 16 + 1: return (double)b[0];
        case 'U' * 16 + 2: { uint16_t v; std::memcpy(&v, b, 2); return v; }
        case 'U' * 16 + 4: { uint32_t v; std::memcpy(&v, b, 4); return v; }
        default: { uint64_t v; std::memcpy(&v, b, 8); return (double)v; }
        }
    }
};

//! One text token as a number ("nan", "inf" and the like included); false if it is none.
bool parseNumber(const std::string& token, double& v)
{
    errno = 0;
    char* end = nullptr;
    v = std::strtod(token.c_str(), &end);
    return end != token.c_str() && *end == 0 && errno != ERANGE;
}

//! Appends (x, y, z, intensity) as a row of out where x, y and z are finite.
void addPoint(std::vector<float>& out, double x, double y, double z, double intensity)
{
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        return;
    out.push_back((float)x);
    out.push_back((float)y);
    out.push_back((float)z);
    out.push_back((float)intensity);
}

Mat toMat(std::vector<float>& rows)
{
    return Mat((int)(rows.size() / 4), 4, CV_32F, rows.data()).clone();
}

/* LZF decompression (liblzf's format, which PCL's binary_compressed uses): a control byte below 32 starts a run of
 that many plus one literal bytes; above, its top 3 bits are the length - 2 of a back-reference (7: one more byte
 adds to it) and its low 5 bits with the next byte the distance - 1. Returns the bytes written, or -1 where the
 stream is inconsistent. */
long long lzfDecompress(const unsigned char* in, size_t inSize, unsigned char* out, size_t outSize)
{
    const unsigned char* ip = in;
    const unsigned char* const inEnd = in + inSize;
    unsigned char* op = out;
    unsigned char* const outEnd = out + outSize;
    while (ip < inEnd)
    {
        const unsigned ctrl = *ip++;
        if (ctrl < 32)
        {
            const size_t len = ctrl + 1;
            if ((size_t)(outEnd - op) < len || (size_t)(inEnd - ip) < len)
                return -1;
            std::memcpy(op, ip, len);
            op += len;
            ip += len;
            continue;
        }
        size_t len = ctrl >> 5;
        if (len == 7)
        {
            if (ip >= inEnd)
                return -1;
            len += *ip++;
        }
        if (ip >= inEnd)
            return -1;
        const size_t distance = ((size_t)(ctrl & 31) << 8) + *ip++ + 1;
        len += 2;
        if ((size_t)(op - out) < distance || (size_t)(outEnd - op) < len)
            return -1;
        const unsigned char* ref = op - distance;
        for (size_t i = 0; i < len; i++)   // byte by byte: the reference may overlap what it writes
            *op++ = *ref++;
    }
    return (long long)(op - out);
}

//! The header line's words after its keyword.
std::vector<std::string> words(std::istringstream& line)
{
    std::vector<std::string> w;
    std::string s;
    while (line >> s)
        w.push_back(s);
    return w;
}

long long parseCount(const String& path, const std::string& key, const std::string& s)
{
    double v = 0;
    if (!parseNumber(s, v) || v < 0 || v != std::floor(v) || v > 1e12)
        fail(path, key + " is not a count: '" + s + "'");
    return (long long)v;
}

//! A PCD file's header lines as given (up to and including DATA), and where its data start.
struct PcdHeader
{
    std::vector<std::string> fields, sizeWords, typeWords, countWords;
    long long width = -1, height = 1, points = -1;
    std::string dataKind;
    size_t dataStart = 0;
};

PcdHeader readPcdHeader(const String& path, const std::vector<char>& file)
{
    PcdHeader h;
    size_t pos = 0;
    while (h.dataKind.empty())
    {
        if (pos >= file.size())
            fail(path, "the header ends before its DATA line");
        const size_t eol = std::find(file.begin() + (std::ptrdiff_t)pos, file.end(), '\n') - file.begin();
        std::istringstream line(std::string(file.data() + pos, eol - pos));
        pos = eol + 1;
        std::string key;
        if (!(line >> key) || key[0] == '#')
            continue;
        const std::vector<std::string> w = words(line);
        if (key == "FIELDS")
            h.fields = w;
        else if (key == "SIZE")
            h.sizeWords = w;
        else if (key == "TYPE")
            h.typeWords = w;
        else if (key == "COUNT")
            h.countWords = w;
        else if (key == "WIDTH" && w.size() == 1)
            h.width = parseCount(path, key, w[0]);
        else if (key == "HEIGHT" && w.size() == 1)
            h.height = parseCount(path, key, w[0]);
        else if (key == "POINTS" && w.size() == 1)
            h.points = parseCount(path, key, w[0]);
        else if (key == "DATA")
        {
            if (w.size() != 1)
                fail(path, "DATA names no kind");
            h.dataKind = w[0];
        }
    }
    h.dataStart = pos;
    return h;
}

/* A PCD record's layout from its header, checked: each field's type and count, its offset in a record (binary) and in
a record's values (ascii), the point count, and which fields are x, y, z and intensity (-1: none). */
struct PcdLayout
{
    std::vector<Scalar> types;
    std::vector<int> counts;
    std::vector<size_t> offset, first;
    size_t step = 0, values = 0;
    long long n = 0;
    int ix = -1, iy = -1, iz = -1, ii = -1;
};

//! Each field's type and count from SIZE, TYPE and COUNT.
void pcdFieldTypes(const String& path, const PcdHeader& h, PcdLayout& l)
{
    const size_t nf = h.fields.size();
    if (nf == 0)
        fail(path, "the header has no FIELDS");
    if (h.sizeWords.size() != nf || h.typeWords.size() != nf || (!h.countWords.empty() && h.countWords.size() != nf))
        fail(path, "SIZE, TYPE and COUNT give " + std::to_string(h.sizeWords.size()) + ", " +
                       std::to_string(h.typeWords.size()) + " and " + std::to_string(h.countWords.size()) +
                       " fields, FIELDS " + std::to_string(nf));
    l.types.assign(nf, Scalar());
    l.counts.assign(nf, 1);
    for (size_t i = 0; i < nf; i++)
    {
        const long long size = parseCount(path, "SIZE", h.sizeWords[i]);
        const std::string& t = h.typeWords[i];
        if (t != "F" && t != "I" && t != "U")
            fail(path, "field " + h.fields[i] + " has type '" + t + "', not F, I or U");
        if ((size != 1 && size != 2 && size != 4 && size != 8) || (t == "F" && size != 4 && size != 8))
            fail(path, "field " + h.fields[i] + " of type " + t + " has " + h.sizeWords[i] + " bytes");
        l.types[i].type = t[0];
        l.types[i].size = (int)size;
        if (!h.countWords.empty())
            l.counts[i] = (int)std::min(parseCount(path, "COUNT", h.countWords[i]), 1LL << 20);
    }
}

PcdLayout pcdLayout(const String& path, const PcdHeader& h)
{
    PcdLayout l;
    pcdFieldTypes(path, h, l);
    if (h.width < 0 && h.points < 0)
        fail(path, "the header has neither WIDTH nor POINTS");
    if ((double)h.width * (double)h.height > 1e12)
        fail(path, "WIDTH x HEIGHT is not a number of points");
    if (h.width >= 0 && h.points >= 0 && h.points != h.width * h.height)
        fail(path, "POINTS " + std::to_string(h.points) + " disagrees with WIDTH x HEIGHT = " +
                       std::to_string(h.width) + " x " + std::to_string(h.height));
    l.n = h.points >= 0 ? h.points : h.width * h.height;
    const size_t nf = h.fields.size();
    l.offset.resize(nf);
    l.first.resize(nf);
    std::vector<std::string> unread;
    for (size_t i = 0; i < nf; i++)
    {
        l.offset[i] = l.step;
        l.first[i] = l.values;
        l.step += (size_t)l.types[i].size * l.counts[i];
        l.values += l.counts[i];
        const std::string& f = h.fields[i];
        int* slot = f == "x" ? &l.ix : f == "y" ? &l.iy : f == "z" ? &l.iz : f == "intensity" ? &l.ii : nullptr;
        if (slot && *slot < 0 && l.counts[i] > 0)   // a field of count > 1 gives its first value
            *slot = (int)i;
        else if (!slot)
            unread.push_back(f);
    }
    noteUnreadFields(path, unread);
    if (l.ix < 0 || l.iy < 0 || l.iz < 0)
        fail(path, "FIELDS has no " + std::string(l.ix < 0 ? "x" : l.iy < 0 ? "y" : "z"));
    return l;
}

Mat readPcdAscii(const String& path, const unsigned char* data, size_t available, const PcdLayout& l)
{
    std::vector<float> out;
    std::istringstream text(std::string((const char*)data, available));
    std::vector<double> record(l.values);
    std::string token;
    for (long long p = 0; p < l.n; p++)
    {
        for (size_t v = 0; v < l.values; v++)
        {
            if (!(text >> token))
                fail(path, "the data ends at point " + std::to_string(p) + " of " + std::to_string(l.n));
            if (!parseNumber(token, record[v]))
                fail(path, "point " + std::to_string(p) + " has '" + token + "' where a number belongs");
        }
        addPoint(out, record[l.first[l.ix]], record[l.first[l.iy]], record[l.first[l.iz]],
                 l.ii >= 0 ? record[l.first[l.ii]] : 0.0);
    }
    if (text >> token)
        fail(path, "more values follow the " + std::to_string(l.n) + " points of the header");
    return toMat(out);
}

Mat readPcdBinary(const String& path, const unsigned char* data, size_t available, const PcdLayout& l)
{
    const double bytes = (double)l.n * (double)l.step;
    if (bytes > (double)available)
        fail(path, "truncated: " + std::to_string(l.n) + " points of " + std::to_string(l.step) + " bytes need " +
                       std::to_string((long long)bytes) + " bytes of data, the file has " + std::to_string(available));
    std::vector<float> out;
    const std::vector<Scalar>& t = l.types;
    for (long long p = 0; p < l.n; p++)
    {
        const unsigned char* r = data + (size_t)p * l.step;
        addPoint(out, t[l.ix].read(r + l.offset[l.ix]), t[l.iy].read(r + l.offset[l.iy]),
                 t[l.iz].read(r + l.offset[l.iz]), l.ii >= 0 ? t[l.ii].read(r + l.offset[l.ii]) : 0.0);
    }
    return toMat(out);
}

//! binary_compressed: two little-endian sizes, then the LZF stream of the fields one after the other (each over all
//! points).
Mat readPcdCompressed(const String& path, const unsigned char* data, size_t available, const PcdLayout& l)
{
    const double bytes = (double)l.n * (double)l.step;
    if (available < 8)
        fail(path, "truncated: binary_compressed data without its two sizes");
    uint32_t packed = 0, unpacked = 0;
    std::memcpy(&packed, data, 4);
    std::memcpy(&unpacked, data + 4, 4);
    if (packed > available - 8)
        fail(path, "truncated: " + std::to_string(packed) + " compressed bytes announced, " +
                       std::to_string(available - 8) + " there");
    if ((double)unpacked != bytes)
        fail(path, "the uncompressed size " + std::to_string(unpacked) + " disagrees with " + std::to_string(l.n) +
                       " points of " + std::to_string(l.step) + " bytes");
    // LZF writes at most 264 bytes for 2 (a back-reference): a larger size cannot come out of this stream.
    if ((double)unpacked > 132.0 * packed + 64.0)
        fail(path, "the uncompressed size " + std::to_string(unpacked) + " cannot come from " +
                       std::to_string(packed) + " compressed bytes");
    std::vector<unsigned char> raw(unpacked);
    if (lzfDecompress(data + 8, packed, raw.data(), raw.size()) != (long long)unpacked)
        fail(path, "the compressed data is corrupt (LZF)");
    // Field i of point p lies at n offset[i] + p size_i count_i.
    auto at = [&](int i, long long p) {
        return l.types[i].read(raw.data() + (size_t)l.n * l.offset[i] + (size_t)p * l.types[i].size * l.counts[i]);
    };
    std::vector<float> out;
    for (long long p = 0; p < l.n; p++)
        addPoint(out, at(l.ix, p), at(l.iy, p), at(l.iz, p), l.ii >= 0 ? at(l.ii, p) : 0.0);
    return toMat(out);
}

Mat readPcd(const String& path, const std::vector<char>& file)
{
    const PcdHeader h = readPcdHeader(path, file);
    const PcdLayout l = pcdLayout(path, h);
    const size_t pos = std::min(h.dataStart, file.size());
    const unsigned char* data = (const unsigned char*)file.data() + pos;
    const size_t available = file.size() - pos;
    if (h.dataKind == "ascii")
        return readPcdAscii(path, data, available, l);
    if (h.dataKind == "binary")
        return readPcdBinary(path, data, available, l);
    if (h.dataKind == "binary_compressed")
        return readPcdCompressed(path, data, available, l);
    fail(path, "unknown DATA kind '" + h.dataKind + "' (ascii, binary or binary_compressed)");
}

//! A PLY property: a scalar, or a list of scalars after its count.
struct PlyProperty
{
    std::string name;
    Scalar value;
    bool list = false;
    Scalar count;
};

struct PlyElement
{
    std::string name;
    long long n = 0;
    std::vector<PlyProperty> props;
};

//! A PLY property type's scalar ("float", "float32", ...).
Scalar plyScalar(const String& path, const std::string& t, bool bigEndian)
{
    static const char* names[][2] = { { "char", "int8" }, { "uchar", "uint8" }, { "short", "int16" },
                                      { "ushort", "uint16" }, { "int", "int32" }, { "uint", "uint32" },
                                      { "float", "float32" }, { "double", "float64" } };
    static const char types[] = { 'I', 'U', 'I', 'U', 'I', 'U', 'F', 'F' };
    static const int sizes[] = { 1, 1, 2, 2, 4, 4, 4, 8 };
    for (int i = 0; i < 8; i++)
        if (t == names[i][0] || t == names[i][1])
        {
            Scalar s;
            s.type = types[i];
            s.size = sizes[i];
            s.bigEndian = bigEndian;
            return s;
        }
    fail(path, "unknown property type '" + t + "'");
}

//! A property line's words (after "property") as the property of the element before it.
void addPlyProperty(const String& path, const std::vector<std::string>& w, const std::string& format,
                    std::vector<PlyElement>& elements)
{
    if (elements.empty() || format.empty())
        fail(path, "a property before its format or element");
    PlyProperty pr;
    const bool big = format == "binary_big_endian";
    if (w.size() == 4 && w[0] == "list")
    {
        pr.list = true;
        pr.count = plyScalar(path, w[1], big);
        pr.value = plyScalar(path, w[2], big);
        pr.name = w[3];
    }
    else if (w.size() == 2)
    {
        pr.value = plyScalar(path, w[0], big);
        pr.name = w[1];
    }
    else
        fail(path, "a property line of " + std::to_string(w.size()) + " words");
    elements.back().props.push_back(pr);
}

//! The header up to end_header: its elements and format; pos receives where the data start.
void readPlyHeader(const String& path, const std::vector<char>& file, std::vector<PlyElement>& elements,
                   std::string& format, size_t& pos)
{
    pos = 0;
    bool first = true, ended = false;
    while (!ended)
    {
        if (pos >= file.size())
            fail(path, "the header ends before end_header");
        const size_t eol = std::find(file.begin() + (std::ptrdiff_t)pos, file.end(), '\n') - file.begin();
        std::string text(file.data() + pos, eol - pos);
        if (!text.empty() && text.back() == '\r')
            text.pop_back();
        pos = eol + 1;
        std::istringstream line(text);
        std::string key;
        line >> key;
        if (first)
        {
            if (key != "ply")
                fail(path, "not a PLY file (no 'ply' line first)");
            first = false;
            continue;
        }
        const std::vector<std::string> w = words(line);
        if (key == "format")
        {
            if (w.empty() || (w[0] != "ascii" && w[0] != "binary_little_endian" && w[0] != "binary_big_endian"))
                fail(path, "unknown format '" + (w.empty() ? std::string() : w[0]) + "'");
            format = w[0];
        }
        else if (key == "element")
        {
            if (w.size() != 2)
                fail(path, "an element line without a name and a count");
            PlyElement e;
            e.name = w[0];
            e.n = parseCount(path, "element " + w[0], w[1]);
            elements.push_back(e);
        }
        else if (key == "property")
            addPlyProperty(path, w, format, elements);
        else if (key == "end_header")
            ended = true;
    }
    if (format.empty())
        fail(path, "the header has no format line");
}

//! The value of property pr of record r of element e in ascii data (a list's last item; 0 for an empty list).
double plyAsciiValue(const String& path, std::istringstream& text, const PlyElement& e, const PlyProperty& pr,
                     long long r)
{
    long long items = 1;
    std::string token;
    double x = 0;
    if (pr.list)
    {
        if (!(text >> token) || !parseNumber(token, x) || x < 0)
            fail(path, "element " + e.name + " " + std::to_string(r) + " has no list count");
        items = (long long)x;
    }
    for (long long k = 0; k < items; k++)
    {
        if (!(text >> token))
            fail(path, "the data ends in element " + e.name + " " + std::to_string(r) + " of " + std::to_string(e.n));
        if (!parseNumber(token, x))
            fail(path, "element " + e.name + " " + std::to_string(r) + " has '" + token + "' where a number belongs");
    }
    return x;
}

//! Property pr of record r of element e in binary data at pos, which moves past it; v receives a scalar's value.
void plyBinaryValue(const String& path, const std::vector<char>& file, size_t& pos, const PlyElement& e,
                    const PlyProperty& pr, long long r, double& v)
{
    long long items = 1;
    if (pr.list)
    {
        if (pos + pr.count.size > file.size())
            fail(path, "truncated in element " + e.name + " " + std::to_string(r));
        const double c = pr.count.read((const unsigned char*)file.data() + pos);
        if (c < 0)
            fail(path, "a negative list count in element " + e.name);
        items = (long long)c;
        pos += pr.count.size;
    }
    const double need = (double)items * pr.value.size;
    if (need > (double)(file.size() - std::min(pos, file.size())))
        fail(path, "truncated in element " + e.name + " " + std::to_string(r) + " of " + std::to_string(e.n));
    if (!pr.list)
        v = pr.value.read((const unsigned char*)file.data() + pos);
    pos += (size_t)need;
}

//! The vertex element's x, y, z and intensity properties (-1: none), the others said once (noteUnreadFields).
void plyVertexSlots(const String& path, const PlyElement& e, int& ix, int& iy, int& iz, int& ii)
{
    std::vector<std::string> unread;
    for (int i = 0; i < (int)e.props.size(); i++)
    {
        const std::string& nm = e.props[i].name;
        int* slot = e.props[i].list ? nullptr : nm == "x" ? &ix : nm == "y" ? &iy : nm == "z" ? &iz
                  : nm == "intensity" ? &ii : nullptr;
        if (slot)
            *slot = i;
        else
            unread.push_back(nm);
    }
    noteUnreadFields(path, unread);
    if (ix < 0 || iy < 0 || iz < 0)
        fail(path, "the vertex element has no " + std::string(ix < 0 ? "x" : iy < 0 ? "y" : "z"));
}

Mat readPly(const String& path, const std::vector<char>& file)
{
    std::vector<PlyElement> elements;
    std::string format;
    size_t pos = 0;
    readPlyHeader(path, file, elements, format, pos);
    std::vector<float> out;
    const bool ascii = format == "ascii";
    std::istringstream text(ascii ? std::string(file.data() + std::min(pos, file.size()), file.size() -
                                                std::min(pos, file.size()))
                                  : std::string());
    // The elements before the vertex element are read past; the vertex element's points are the cloud.
    for (const PlyElement& e : elements)
    {
        const bool vertex = e.name == "vertex";
        int ix = -1, iy = -1, iz = -1, ii = -1;
        if (vertex)
            plyVertexSlots(path, e, ix, iy, iz, ii);
        std::vector<double> v(e.props.size());
        for (long long r = 0; r < e.n; r++)
        {
            for (size_t i = 0; i < e.props.size(); i++)
            {
                if (ascii)
                    v[i] = plyAsciiValue(path, text, e, e.props[i], r);
                else
                    plyBinaryValue(path, file, pos, e, e.props[i], r, v[i]);
            }
            if (vertex)
                addPoint(out, v[ix], v[iy], v[iz], ii >= 0 ? v[ii] : 0.0);
        }
        if (vertex)
            return toMat(out);
    }
    fail(path, "no vertex element");
}

bool endsWith(const std::string& s, const char* suffix)
{
    const size_t n = std::strlen(suffix);
    if (s.size() < n)
        return false;
    for (size_t i = 0; i < n; i++)
        if (std::tolower((unsigned char)s[s.size() - n + i]) != suffix[i])
            return false;
    return true;
}

} // namespace

Mat readPointCloud(const String& path)
{
    if (endsWith(path, ".bin"))
    {
        const Mat scan = readVelodyneScan(path);
        std::vector<float> out;
        out.reserve(scan.total());
        for (int i = 0; i < scan.rows; i++)
        {
            const float* p = scan.ptr<float>(i);
            addPoint(out, p[0], p[1], p[2], p[3]);
        }
        return toMat(out);
    }
    if (!endsWith(path, ".pcd") && !endsWith(path, ".ply"))
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm: point cloud " + path + ": unknown file type (.pcd, .ply or .bin)");
    const std::vector<char> file = readFile(path);
    return endsWith(path, ".pcd") ? readPcd(path, file) : readPly(path, file);
}

}} // namespace cv::lidarsgm
