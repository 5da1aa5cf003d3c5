// Writes the seed corpora of the fuzz targets: `fuzz_corpus DIR` creates DIR/skeleton/ (small
// synthetic databases, textured and untextured) and DIR/blob/ (each of their blobs, prefixed
// with the selector byte fuzz_blob expects: 0 Draco, 1 JPEG, 2 PNG).
#include "formats/codec.h"
#include "tests/support/synthetic.h"

#include <filesystem>
#include <fstream>
#include <iostream>

namespace {

void save(const std::filesystem::path& path, uint8_t prefix, const std::vector<uint8_t>& bytes, bool withPrefix) {
    std::ofstream out(path, std::ios::binary);
    if (withPrefix) out.put(char(prefix));
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: fuzz_corpus DIR\n";
        return 2;
    }
    namespace fs = std::filesystem;
    const fs::path dir = argv[1];
    fs::create_directories(dir / "skeleton");
    fs::create_directories(dir / "blob");
    try {
        for (uint32_t textureSize : {8u, 0u}) {
            hlod::SyntheticOptions o;
            o.blocksX = 1;
            o.blocksY = 1;
            o.levels = 2;
            o.levelFactor = 2;
            o.trianglesPerNode = 8;
            o.textureSize = textureSize;
            const fs::path db = dir / "skeleton" / ("synthetic-" + std::to_string(textureSize) + ".hlod");
            hlod::writeSyntheticDatabase(db.string(), o);
            hlod::Database d = hlod::Database::open(db.string());
            for (uint32_t i = 0; i < d.skeleton().blobs.size(); ++i) {
                const hlod::BlobRef& b = d.skeleton().blobs[i];
                uint8_t selector = b.codec == hlod::Codec::Draco ? 0 : b.codec == hlod::Codec::Jpeg ? 1 : 2;
                save(dir / "blob" / ("t" + std::to_string(textureSize) + "-" + std::to_string(i)), selector,
                     d.readBlob(i), true);
            }
        }
        hlod::Image img{4, 4, 4, std::vector<uint8_t>(64, 200)};
        save(dir / "blob" / "png-rgba", 2, hlod::encodeTexture(img, hlod::Codec::Png).bytes, true);
    } catch (const std::exception& e) {
        std::cerr << "fuzz_corpus: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
