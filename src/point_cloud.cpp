// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// LiDAR point clouds from files: PCD (PCL's format), PLY and KITTI's .bin, as N x 4 float (x, y, z, intensity).
// Parsers of untrusted files: every size is checked against the bytes there before anything is read or allocated.

#include "precomp.hpp"
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

Mat readPcd(const String& path, const std::vector<char>& file)
{
    // The header: lines up to and including DATA.
    std::vector<std::string> fields, sizeWords, typeWords, countWords;
    long long width = -1, height = 1, points = -1;
    std::string dataKind;
    size_t pos = 0;
    while (dataKind.empty())
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
            fields = w;
        else if (key == "SIZE")
            sizeWords = w;
        else if (key == "TYPE")
            typeWords = w;
        else if (key == "COUNT")
            countWords = w;
        else if (key == "WIDTH" && w.size() == 1)
            width = parseCount(path, key, w[0]);
        else if (key == "HEIGHT" && w.size() == 1)
            height = parseCount(path, key, w[0]);
        else if (key == "POINTS" && w.size() == 1)
            points = parseCount(path, key, w[0]);
        else if (key == "DATA")
        {
            if (w.size() != 1)
                fail(path, "DATA names no kind");
            dataKind = w[0];
        }
    }
    const size_t nf = fields.size();
    if (nf == 0)
        fail(path, "the header has no FIELDS");
    if (sizeWords.size() != nf || typeWords.size() != nf || (!countWords.empty() && countWords.size() != nf))
        fail(path, "SIZE, TYPE and COUNT give " + std::to_string(sizeWords.size()) + ", " +
                       std::to_string(typeWords.size()) + " and " + std::to_string(countWords.size()) +
                       " fields, FIELDS " + std::to_string(nf));
    std::vector<Scalar> types(nf);
    std::vector<int> counts(nf, 1);
    for (size_t i = 0; i < nf; i++)
    {
        const long long size = parseCount(path, "SIZE", sizeWords[i]);
        const std::string& t = typeWords[i];
        if (t != "F" && t != "I" && t != "U")
            fail(path, "field " + fields[i] + " has type '" + t + "', not F, I or U");
        if ((size != 1 && size != 2 && size != 4 && size != 8) || (t == "F" && size != 4 && size != 8))
            fail(path, "field " + fields[i] + " of type " + t + " has " + sizeWords[i] + " bytes");
        types[i].type = t[0];
        types[i].size = (int)size;
        if (!countWords.empty())
            counts[i] = (int)std::min(parseCount(path, "COUNT", countWords[i]), 1LL << 20);
    }
    if (width < 0 && points < 0)
        fail(path, "the header has neither WIDTH nor POINTS");
    if ((double)width * (double)height > 1e12)
        fail(path, "WIDTH x HEIGHT is not a number of points");
    if (width >= 0 && points >= 0 && points != width * height)
        fail(path, "POINTS " + std::to_string(points) + " disagrees with WIDTH x HEIGHT = " +
                       std::to_string(width) + " x " + std::to_string(height));
    const long long n = points >= 0 ? points : width * height;
    // Each field's offset in a record (binary) and in a record's values (ascii); x, y, z and intensity.
    std::vector<size_t> offset(nf), first(nf);
    size_t step = 0, values = 0;
    int ix = -1, iy = -1, iz = -1, ii = -1;
    std::vector<std::string> unread;
    for (size_t i = 0; i < nf; i++)
    {
        offset[i] = step;
        first[i] = values;
        step += (size_t)types[i].size * counts[i];
        values += counts[i];
        int* slot = fields[i] == "x" ? &ix : fields[i] == "y" ? &iy : fields[i] == "z" ? &iz
                  : fields[i] == "intensity" ? &ii : nullptr;
        if (slot && *slot < 0 && counts[i] > 0)   // a field of count > 1 gives its first value
            *slot = (int)i;
        else if (!slot)
            unread.push_back(fields[i]);
    }
    noteUnreadFields(path, unread);
    if (ix < 0 || iy < 0 || iz < 0)
        fail(path, "FIELDS has no " + std::string(ix < 0 ? "x" : iy < 0 ? "y" : "z"));

    std::vector<float> out;
    const unsigned char* data = (const unsigned char*)file.data() + std::min(pos, file.size());
    const size_t available = file.size() - std::min(pos, file.size());
    if (dataKind == "ascii")
    {
        std::istringstream text(std::string((const char*)data, available));
        std::vector<double> record(values);
        std::string token;
        for (long long p = 0; p < n; p++)
        {
            for (size_t v = 0; v < values; v++)
            {
                if (!(text >> token))
                    fail(path, "the data ends at point " + std::to_string(p) + " of " + std::to_string(n));
                if (!parseNumber(token, record[v]))
                    fail(path, "point " + std::to_string(p) + " has '" + token + "' where a number belongs");
            }
            addPoint(out, record[first[ix]], record[first[iy]], record[first[iz]], ii >= 0 ? record[first[ii]] : 0.0);
        }
        if (text >> token)
            fail(path, "more values follow the " + std::to_string(n) + " points of the header");
        return toMat(out);
    }
    const double bytes = (double)n * (double)step;
    if (dataKind == "binary")
    {
        if (bytes > (double)available)
            fail(path, "truncated: " + std::to_string(n) + " points of " + std::to_string(step) + " bytes need " +
                           std::to_string((long long)bytes) + " bytes of data, the file has " +
                           std::to_string(available));
        for (long long p = 0; p < n; p++)
        {
            const unsigned char* r = data + (size_t)p * step;
            addPoint(out, types[ix].read(r + offset[ix]), types[iy].read(r + offset[iy]),
                     types[iz].read(r + offset[iz]), ii >= 0 ? types[ii].read(r + offset[ii]) : 0.0);
        }
        return toMat(out);
    }
    if (dataKind == "binary_compressed")
    {
        // Two little-endian sizes, then the LZF stream of the fields one after the other (each over all points).
        if (available < 8)
            fail(path, "truncated: binary_compressed data without its two sizes");
        uint32_t packed = 0, unpacked = 0;
        std::memcpy(&packed, data, 4);
        std::memcpy(&unpacked, data + 4, 4);
        if (packed > available - 8)
            fail(path, "truncated: " + std::to_string(packed) + " compressed bytes announced, " +
                           std::to_string(available - 8) + " there");
        if ((double)unpacked != bytes)
            fail(path, "the uncompressed size " + std::to_string(unpacked) + " disagrees with " + std::to_string(n) +
                           " points of " + std::to_string(step) + " bytes");
        // LZF writes at most 264 bytes for 2 (a back-reference): a larger size cannot come out of this stream.
        if ((double)unpacked > 132.0 * packed + 64.0)
            fail(path, "the uncompressed size " + std::to_string(unpacked) + " cannot come from " +
                           std::to_string(packed) + " compressed bytes");
        std::vector<unsigned char> raw(unpacked);
        if (lzfDecompress(data + 8, packed, raw.data(), raw.size()) != (long long)unpacked)
            fail(path, "the compressed data is corrupt (LZF)");
        // Field i of point p lies at n offset[i] + p size_i count_i.
        auto at = [&](int i, long long p) {
            return types[i].read(raw.data() + (size_t)n * offset[i] + (size_t)p * types[i].size * counts[i]);
        };
        for (long long p = 0; p < n; p++)
            addPoint(out, at(ix, p), at(iy, p), at(iz, p), ii >= 0 ? at(ii, p) : 0.0);
        return toMat(out);
    }
    fail(path, "unknown DATA kind '" + dataKind + "' (ascii, binary or binary_compressed)");
}

Mat readPly(const String& path, const std::vector<char>& file)
{
    struct Property
    {
        std::string name;
        Scalar value;
        bool list = false;
        Scalar count;
    };
    struct Element
    {
        std::string name;
        long long n = 0;
        std::vector<Property> props;
    };
    auto scalarOf = [&](const std::string& t, bool bigEndian) {
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
    };
    std::vector<Element> elements;
    std::string format;
    size_t pos = 0;
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
            Element e;
            e.name = w[0];
            e.n = parseCount(path, "element " + w[0], w[1]);
            elements.push_back(e);
        }
        else if (key == "property")
        {
            if (elements.empty() || format.empty())
                fail(path, "a property before its format or element");
            Property pr;
            const bool big = format == "binary_big_endian";
            if (w.size() == 4 && w[0] == "list")
            {
                pr.list = true;
                pr.count = scalarOf(w[1], big);
                pr.value = scalarOf(w[2], big);
                pr.name = w[3];
            }
            else if (w.size() == 2)
            {
                pr.value = scalarOf(w[0], big);
                pr.name = w[1];
            }
            else
                fail(path, "a property line of " + std::to_string(w.size()) + " words");
            elements.back().props.push_back(pr);
        }
        else if (key == "end_header")
            ended = true;
    }
    if (format.empty())
        fail(path, "the header has no format line");

    std::vector<float> out;
    const bool ascii = format == "ascii";
    std::istringstream text(ascii ? std::string(file.data() + std::min(pos, file.size()), file.size() -
                                                std::min(pos, file.size()))
                                  : std::string());
    for (const Element& e : elements)
    {
        const bool vertex = e.name == "vertex";
        int ix = -1, iy = -1, iz = -1, ii = -1;
        std::vector<std::string> unread;
        for (int i = 0; i < (int)e.props.size(); i++)
        {
            const std::string& nm = e.props[i].name;
            int* slot = e.props[i].list ? nullptr : nm == "x" ? &ix : nm == "y" ? &iy : nm == "z" ? &iz
                      : nm == "intensity" ? &ii : nullptr;
            if (slot)
                *slot = i;
            else if (vertex)
                unread.push_back(nm);
        }
        if (vertex)
            noteUnreadFields(path, unread);
        if (vertex && (ix < 0 || iy < 0 || iz < 0))
            fail(path, "the vertex element has no " + std::string(ix < 0 ? "x" : iy < 0 ? "y" : "z"));
        std::vector<double> v(e.props.size());
        for (long long r = 0; r < e.n; r++)
        {
            for (size_t i = 0; i < e.props.size(); i++)
            {
                const Property& pr = e.props[i];
                long long items = 1;
                if (ascii)
                {
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
                            fail(path, "the data ends in element " + e.name + " " + std::to_string(r) + " of " +
                                           std::to_string(e.n));
                        if (!parseNumber(token, x))
                            fail(path, "element " + e.name + " " + std::to_string(r) + " has '" + token +
                                           "' where a number belongs");
                    }
                    v[i] = x;
                }
                else
                {
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
                        fail(path, "truncated in element " + e.name + " " + std::to_string(r) + " of " +
                                       std::to_string(e.n));
                    if (!pr.list)
                        v[i] = pr.value.read((const unsigned char*)file.data() + pos);
                    pos += (size_t)need;
                }
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
