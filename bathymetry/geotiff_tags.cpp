// Minimal TIFF directory walker for the GeoTIFF tags (see geotiff_tags.h).
// TIFF 6.0 section 2 (header, IFD layout); BigTIFF (Aware Systems spec); GeoTIFF 1.1 (OGC 19-008r4)
// for tags 33550, 33922, 34264, 34735 and the GeoKey directory layout.
#include "bathymetry/geotiff_tags.h"

#include <cstdint>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral::bathymetry {

namespace {

// Bytes of a TIFF file, from the file itself or from memory.
class TiffReader {
public:
    TiffReader(const std::filesystem::path& path) : name_(path.string()), in_(path, std::ios::binary) {
        if (!in_) throw InputError(SourceLoc{name_}, "cannot open file (missing or unreadable)");
        in_.seekg(0, std::ios::end);
        size_ = static_cast<uint64_t>(in_.tellg());
    }
    TiffReader(std::string_view data, const std::string& name) : name_(name), mem_(data), inMemory_(true) {
        size_ = data.size();
    }

    uint64_t size() const { return size_; }
    bool little = true;

    [[noreturn]] void corrupt(const std::string& what) const {
        throw InputError(SourceLoc{name_}, "corrupt TIFF: " + what);
    }

    void read(uint64_t offset, void* dst, uint64_t n) {
        if (offset > size_ || n > size_ - offset)
            corrupt(fmt::format("data at offset {} (+{} bytes) lies beyond the end of the {}-byte file", offset, n,
                                size_));
        if (n == 0) return;
        if (inMemory_) {
            std::memcpy(dst, mem_.data() + offset, n);
            return;
        }
        in_.seekg(static_cast<std::streamoff>(offset));
        in_.read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
        if (!in_) corrupt(fmt::format("read failed at offset {}", offset));
    }

    // Unsigned integer of `bytes` bytes from a buffer in the file's byte order.
    uint64_t uint(const unsigned char* p, int bytes) const {
        uint64_t v = 0;
        for (int i = 0; i < bytes; ++i) {
            const uint64_t b = p[little ? i : bytes - 1 - i];
            v |= b << (8 * i);
        }
        return v;
    }

private:
    std::string name_;
    std::ifstream in_;
    std::string_view mem_;
    bool inMemory_ = false;
    uint64_t size_ = 0;
};

int typeSize(uint16_t type) {
    switch (type) {
        case 1: case 2: case 6: case 7: return 1;   // BYTE, ASCII, SBYTE, UNDEFINED
        case 3: case 8: return 2;                    // SHORT, SSHORT
        case 4: case 9: case 11: case 13: return 4;  // LONG, SLONG, FLOAT, IFD
        case 5: case 10: case 12: case 16: case 17: case 18: return 8;  // RATIONALs, DOUBLE, LONG8, SLONG8, IFD8
        default: return 0;
    }
}

}  // namespace

namespace {

// The byte order (set on `r`), the flavour (classic or BigTIFF) and the offset of the first
// directory from the header; false if the file is not a TIFF.
bool readTiffHeader(TiffReader& r, bool* big, uint64_t* ifd) {
    if (r.size() < 8) return false;
    unsigned char hdr[16] = {};
    r.read(0, hdr, std::min<uint64_t>(16, r.size()));
    if (hdr[0] == 'I' && hdr[1] == 'I') r.little = true;
    else if (hdr[0] == 'M' && hdr[1] == 'M') r.little = false;
    else return false;
    const uint64_t magic = r.uint(hdr + 2, 2);
    if (magic == 42) {
        *big = false;
        *ifd = r.uint(hdr + 4, 4);
        return true;
    }
    if (magic == 43) {
        if (r.size() < 16 || r.uint(hdr + 4, 2) != 8) r.corrupt("BigTIFF header has an offset size other than 8");
        *big = true;
        *ifd = r.uint(hdr + 8, 8);
        return true;
    }
    return false;
}

// The values of directory entries (classic TIFF or BigTIFF layout).
class EntryValues {
public:
    EntryValues(TiffReader& r, bool big) : r_(r), big_(big) {}

    // Values of one entry as raw bytes (inline or at the offset), size-checked.
    std::vector<unsigned char> bytes(const unsigned char* e, uint16_t tag, uint16_t type, uint64_t count) {
        const int ts = typeSize(type);
        if (ts == 0) r_.corrupt(fmt::format("tag {} has unknown field type {}", tag, type));
        if (count > (uint64_t(16) << 20) / ts) r_.corrupt(fmt::format("tag {} claims {} values", tag, count));
        std::vector<unsigned char> buf(count * ts);
        const unsigned char* field = e + 4 + (big_ ? 8 : 4);
        if (buf.empty()) return buf;  // a tag with no values (memcpy must not see the null data pointer)
        const int inlineBytes = big_ ? 8 : 4;
        if (buf.size() <= uint64_t(inlineBytes)) std::memcpy(buf.data(), field, buf.size());
        else r_.read(r_.uint(field, inlineBytes), buf.data(), buf.size());
        return buf;
    }

    std::vector<double> doubles(const unsigned char* e, uint16_t tag, uint16_t type, uint64_t count) {
        if (type != 12) r_.corrupt(fmt::format("GeoTIFF tag {} must be DOUBLE (type 12), found type {}", tag, type));
        const auto buf = bytes(e, tag, type, count);
        std::vector<double> out(count);
        for (uint64_t i = 0; i < count; ++i) {
            const uint64_t bits = r_.uint(buf.data() + 8 * i, 8);
            std::memcpy(&out[i], &bits, 8);
        }
        return out;
    }

private:
    TiffReader& r_;
    bool big_;
};

// GeoKeyDirectoryTag: header (version, rev, minor, nkeys) + nkeys x 4 shorts.
void readGeoKeyDirectory(TiffReader& r, EntryValues& values, const unsigned char* e, uint16_t tag, uint16_t type,
                         uint64_t count, GeoTiffInfo& info) {
    if (type != 3) r.corrupt(fmt::format("GeoKeyDirectory must be SHORT (type 3), found type {}", type));
    const auto buf = values.bytes(e, tag, type, count);
    const auto s = [&](uint64_t i) { return static_cast<int>(r.uint(buf.data() + 2 * i, 2)); };
    if (count < 4) r.corrupt("GeoKeyDirectory shorter than its 4-value header");
    const uint64_t keys = static_cast<uint64_t>(s(3));
    if (4 + 4 * keys > count) r.corrupt(fmt::format("GeoKeyDirectory claims {} keys but holds {} values", keys, count));
    for (uint64_t i = 0; i < keys; ++i) {
        const int id = s(4 + 4 * i), location = s(5 + 4 * i), value = s(7 + 4 * i);
        if (location != 0) continue;  // only keys stored inline as SHORT are needed here
        if (id == 1024) info.modelType = value;
        else if (id == 1025) info.rasterType = value;
        else if (id == 3072) info.projectedCrs = value;
    }
}

// One directory entry `e` into `info` (the tags it does not need are skipped).
void readEntry(TiffReader& r, EntryValues& values, const unsigned char* e, bool big, GeoTiffInfo& info) {
    const auto tag = static_cast<uint16_t>(r.uint(e, 2));
    const auto type = static_cast<uint16_t>(r.uint(e + 2, 2));
    const uint64_t count = r.uint(e + 4, big ? 8 : 4);
    switch (tag) {
        case 33550: {  // ModelPixelScaleTag
            const auto v = values.doubles(e, tag, type, count);
            if (v.size() < 2) r.corrupt("ModelPixelScale has fewer than 2 values");
            info.pixelScale = std::array<double, 3>{v[0], v[1], v.size() > 2 ? v[2] : 0.0};
            break;
        }
        case 33922: {  // ModelTiepointTag
            info.tiepoints = values.doubles(e, tag, type, count);
            if (info.tiepoints.size() % 6 != 0)
                r.corrupt(fmt::format("ModelTiepoint has {} values, not a multiple of 6", info.tiepoints.size()));
            break;
        }
        case 34264: {  // ModelTransformationTag
            const auto v = values.doubles(e, tag, type, count);
            if (v.size() != 16) r.corrupt(fmt::format("ModelTransformation has {} values, not 16", v.size()));
            std::array<double, 16> m{};
            std::copy(v.begin(), v.end(), m.begin());
            info.transformation = m;
            break;
        }
        case 34735: readGeoKeyDirectory(r, values, e, tag, type, count, info); break;
        case 42113: {  // GDAL_NODATA, ASCII
            const auto buf = values.bytes(e, tag, type, count);
            std::string s(buf.begin(), buf.end());
            while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
            info.gdalNodata = s;
            break;
        }
        default: break;
    }
}

GeoTiffInfo readInfo(TiffReader& r) {
    GeoTiffInfo info;
    bool big = false;
    uint64_t ifd = 0;
    if (!readTiffHeader(r, &big, &ifd)) return info;
    info.isTiff = true;

    const int countBytes = big ? 8 : 2, entryBytes = big ? 20 : 12;
    unsigned char cnt[8];
    r.read(ifd, cnt, countBytes);
    const uint64_t n = r.uint(cnt, countBytes);
    if (n == 0 || n > 4096) r.corrupt(fmt::format("first directory claims {} entries (allowed 1..4096)", n));
    std::vector<unsigned char> entries(n * entryBytes);
    r.read(ifd + countBytes, entries.data(), entries.size());
    EntryValues values(r, big);
    for (uint64_t k = 0; k < n; ++k) readEntry(r, values, entries.data() + k * entryBytes, big, info);
    return info;
}

}  // namespace

GeoTiffInfo readGeoTiffInfo(const std::filesystem::path& path) {
    TiffReader r(path);
    return readInfo(r);
}

GeoTiffInfo parseGeoTiffInfo(std::string_view data, const std::string& name) {
    TiffReader r(data, name);
    return readInfo(r);
}

}  // namespace littoral::bathymetry
