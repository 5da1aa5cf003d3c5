// The 3D Tiles archive (.3tz, "3D Tiles Archive Format" 1.x, as read by CesiumGS 3d-tiles-tools):
// a ZIP (PKWARE APPNOTE 6.3) whose entries are stored without compression, tileset.json at its
// root, and a last entry "@3dtilesIndex1@" holding, per entry, the MD5 of its path (16 bytes) and
// the offset of its local file header (u64 LE), sorted by the hash read as two little-endian u64
// (the first 8 bytes, then the last 8), so a reader finds a file by binary search. Dates are fixed
// (1980-01-01) so the same tileset gives the same bytes. No ZIP64: at most 65,535 entries and
// 4 GiB; larger tilesets are exported as folders (README: `npx 3d-tiles-tools convert`).
#include "formats/tiles_detail.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace hlod::tiles {

namespace {

namespace fs = std::filesystem;

// MD5 (RFC 1321).
std::array<uint8_t, 16> md5(const std::string& message) {
    static constexpr uint32_t K[64] = {
        0xd76aa478, 0xe8c7b756, 0x242070db, 0xc1bdceee, 0xf57c0faf, 0x4787c62a, 0xa8304613, 0xfd469501,
        0x698098d8, 0x8b44f7af, 0xffff5bb1, 0x895cd7be, 0x6b901122, 0xfd987193, 0xa679438e, 0x49b40821,
        0xf61e2562, 0xc040b340, 0x265e5a51, 0xe9b6c7aa, 0xd62f105d, 0x02441453, 0xd8a1e681, 0xe7d3fbc8,
        0x21e1cde6, 0xc33707d6, 0xf4d50d87, 0x455a14ed, 0xa9e3e905, 0xfcefa3f8, 0x676f02d9, 0x8d2a4c8a,
        0xfffa3942, 0x8771f681, 0x6d9d6122, 0xfde5380c, 0xa4beea44, 0x4bdecfa9, 0xf6bb4b60, 0xbebfbc70,
        0x289b7ec6, 0xeaa127fa, 0xd4ef3085, 0x04881d05, 0xd9d4d039, 0xe6db99e5, 0x1fa27cf8, 0xc4ac5665,
        0xf4292244, 0x432aff97, 0xab9423a7, 0xfc93a039, 0x655b59c3, 0x8f0ccc92, 0xffeff47d, 0x85845dd1,
        0x6fa87e4f, 0xfe2ce6e0, 0xa3014314, 0x4e0811a1, 0xf7537e82, 0xbd3af235, 0x2ad7d2bb, 0xeb86d391};
    static constexpr int R[16] = {7, 12, 17, 22, 5, 9, 14, 20, 4, 11, 16, 23, 6, 10, 15, 21};
    std::vector<uint8_t> m(message.begin(), message.end());
    const uint64_t bits = uint64_t(message.size()) * 8;
    m.push_back(0x80);
    while (m.size() % 64 != 56) m.push_back(0);
    for (int i = 0; i < 8; ++i) m.push_back(uint8_t(bits >> (8 * i)));
    uint32_t h[4] = {0x67452301, 0xefcdab89, 0x98badcfe, 0x10325476};
    for (size_t chunk = 0; chunk < m.size(); chunk += 64) {
        uint32_t w[16];
        std::memcpy(w, m.data() + chunk, 64);  // little-endian host (formats/layout.h)
        uint32_t a = h[0], b = h[1], c = h[2], d = h[3];
        for (int i = 0; i < 64; ++i) {
            uint32_t f;
            int g;
            if (i < 16) f = (b & c) | (~b & d), g = i;
            else if (i < 32) f = (d & b) | (~d & c), g = (5 * i + 1) % 16;
            else if (i < 48) f = b ^ c ^ d, g = (3 * i + 5) % 16;
            else f = c ^ (b | ~d), g = (7 * i) % 16;
            const uint32_t sum = a + f + K[i] + w[g];
            const int r = R[(i / 16) * 4 + i % 4];
            a = d, d = c, c = b;
            b += (sum << r) | (sum >> (32 - r));
        }
        h[0] += a, h[1] += b, h[2] += c, h[3] += d;
    }
    std::array<uint8_t, 16> out;
    std::memcpy(out.data(), h, 16);
    return out;
}

uint64_t hashHalf(const std::array<uint8_t, 16>& hash, int half) {
    uint64_t v;
    std::memcpy(&v, hash.data() + 8 * half, 8);
    return v;
}

struct Zip {
    std::ofstream out;
    std::string path;
    std::vector<uint8_t> central;
    uint64_t offset = 0;
    uint32_t entries = 0;

    template <class T>
    static void put(std::vector<uint8_t>& v, T value) {  // little-endian host (formats/layout.h)
        const auto* bytes = reinterpret_cast<const uint8_t*>(&value);
        v.insert(v.end(), bytes, bytes + sizeof(T));
    }
    void write(const std::vector<uint8_t>& bytes) {
        errno = 0;
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        if (!out) throw std::runtime_error(writeFailure(path, errno));  // at once: its reason, no more work
        offset += bytes.size();
    }
    // Appends one stored entry; returns the offset of its local header.
    uint64_t add(const std::string& name, const std::vector<uint8_t>& data) {
        const uint64_t at = offset;
        if (entries == 0xFFFF || at + 30 + name.size() + data.size() > 0xFFFFFFFFu || data.size() > 0xFFFFFFFFu)
            throw std::runtime_error(path + ": more than 65,535 files or 4 GiB need ZIP64, which --3tz does not write "
                                            "(export a folder and convert it with 3d-tiles-tools)");
        const uint32_t crc = uint32_t(crc32(0, data.data(), uInt(data.size())));
        std::vector<uint8_t> local;
        auto common = [&](std::vector<uint8_t>& v) {
            put<uint16_t>(v, 20);      // version needed: 2.0
            put<uint16_t>(v, 0x0800);  // flags: UTF-8 names
            put<uint16_t>(v, 0);       // stored
            put<uint16_t>(v, 0);       // time 00:00
            put<uint16_t>(v, 0x21);    // date 1980-01-01
            put<uint32_t>(v, crc);
            put<uint32_t>(v, uint32_t(data.size()));
            put<uint32_t>(v, uint32_t(data.size()));
            put<uint16_t>(v, uint16_t(name.size()));
            put<uint16_t>(v, 0);  // extra field
        };
        put<uint32_t>(local, 0x04034b50);
        common(local);
        local.insert(local.end(), name.begin(), name.end());
        write(local);
        write(data);
        put<uint32_t>(central, 0x02014b50);
        put<uint16_t>(central, 20);  // made by: 2.0
        common(central);
        put<uint16_t>(central, 0);  // comment
        put<uint16_t>(central, 0);  // disk
        put<uint16_t>(central, 0);  // internal attributes
        put<uint32_t>(central, 0);  // external attributes
        put<uint32_t>(central, uint32_t(at));
        central.insert(central.end(), name.begin(), name.end());
        ++entries;
        return at;
    }
    void finish() {
        const uint64_t centralOffset = offset;
        std::vector<uint8_t> end;
        put<uint32_t>(end, 0x06054b50);
        put<uint16_t>(end, 0);
        put<uint16_t>(end, 0);
        put<uint16_t>(end, uint16_t(entries));
        put<uint16_t>(end, uint16_t(entries));
        put<uint32_t>(end, uint32_t(central.size()));
        put<uint32_t>(end, uint32_t(centralOffset));
        put<uint16_t>(end, 0);
        write(central);
        write(end);
        errno = 0;
        out.close();
        if (!out) throw std::runtime_error(writeFailure(path, errno));
    }
};

std::vector<uint8_t> readAll(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (!in.eof() && in.fail()) throw std::runtime_error(file.string() + ": cannot read");
    return bytes;
}

}  // namespace

void write3tz(const std::string& folder, const std::string& file) {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(folder))
        if (e.is_regular_file()) names.push_back(fs::relative(e.path(), folder).generic_string());
    std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
        if (a == "tileset.json" || b == "tileset.json") return a == "tileset.json" && b != a;  // first
        return a < b;
    });
    Zip zip{std::ofstream(file, std::ios::binary | std::ios::trunc), file, {}, 0, 0};
    if (!zip.out) throw std::runtime_error(writeFailure(file, errno));
    std::vector<std::pair<std::array<uint8_t, 16>, uint64_t>> index;
    for (const std::string& name : names) index.emplace_back(md5(name), zip.add(name, readAll(fs::path(folder) / name)));
    std::sort(index.begin(), index.end(), [](const auto& a, const auto& b) {
        return std::pair(hashHalf(a.first, 0), hashHalf(a.first, 1)) < std::pair(hashHalf(b.first, 0), hashHalf(b.first, 1));
    });
    std::vector<uint8_t> bytes;
    for (const auto& [hash, offset] : index) {
        bytes.insert(bytes.end(), hash.begin(), hash.end());
        Zip::put<uint64_t>(bytes, offset);
    }
    zip.add("@3dtilesIndex1@", bytes);
    zip.finish();
}

}  // namespace hlod::tiles
