// `hlod inspect DB [--tree [--depth N]] [--node ID] [--json]`: the per-level summary (nodes,
// triangles, texels, bytes, constants, provenance), the node tree, or one node in full
// (thesis §3.3 attributes + FORMAT.md extensions).
#include "formats/cli/subcommands.h"

#include "formats/inspect.h"
#include "formats/errors.h"
#include "formats/json_text.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

namespace hlod::cli {

namespace {

struct InspectArgs {
    std::string path;
    bool tree = false;
    uint32_t depth = 0;
    std::optional<uint32_t> node;
    bool json = false;
};

std::string bytesText(uint64_t b) {
    char buf[32];
    if (b < 10 * 1024) std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(b));
    else if (b < 10ull << 20) std::snprintf(buf, sizeof buf, "%.1f KiB", b / 1024.0);
    else std::snprintf(buf, sizeof buf, "%.1f MiB", b / 1048576.0);
    return buf;
}

void printSummary(const DatabaseSummary& s) {
    std::printf("%s: HLOD database %u.%u, %s\n", s.path.c_str(), s.major, s.minor, bytesText(s.fileSize).c_str());
    std::printf("nodes %llu, blobs %llu, blocks %llu, levels %zu, depth %u\n", (unsigned long long)s.nodes,
                (unsigned long long)s.blobs, (unsigned long long)s.blocks, s.levels.size(), s.depth);
    std::printf("%5s %7s %12s %12s %10s %12s %12s %12s %10s\n", "level", "nodes", "textured", "untextured", "vertices",
                "texels", "geometry", "textures", "max error");
    for (const LevelSummary& L : s.levels)
        std::printf("%5u %7llu %12llu %12llu %10llu %12llu %12s %12s %10.4g\n", L.level, (unsigned long long)L.nodes,
                    (unsigned long long)L.texturedTriangles, (unsigned long long)L.untexturedTriangles,
                    (unsigned long long)L.vertices, (unsigned long long)L.texels, bytesText(L.geometryBytes).c_str(),
                    bytesText(L.textureBytes).c_str(), L.maxGeometricError);
    std::printf("constants:");
    for (const auto& [k, v] : s.constants) std::printf(" %s=%s", k.c_str(), v.c_str());
    std::printf("\nprovenance:\n");
    for (const auto& [k, v] : s.provenance) std::printf("  %s: %s\n", printableLine(k).c_str(), printableLine(v).c_str());
}

void printTree(const nlohmann::json& nodes, int indent) {
    for (const auto& n : nodes) {
        std::printf("%*snode %u  level %u  block %u  %u tris  %llu texels  %s  error %.4g\n", indent * 2, "",
                    n["id"].get<uint32_t>(), n["level"].get<uint32_t>(), n["block"].get<uint32_t>(),
                    n["triangles"].get<uint32_t>(), (unsigned long long)n["texels"].get<uint64_t>(),
                    bytesText(n["bytes"].get<uint64_t>()).c_str(), n["error"].get<double>());
        if (n.contains("children_not_shown"))
            std::printf("%*s(%u children not shown)\n", indent * 2 + 2, "", n["children_not_shown"].get<uint32_t>());
        else printTree(n["children"], indent + 1);
    }
}

void printNode(const nlohmann::json& n) {
    for (const auto& [key, value] : n.items()) {
        if (key == "blobs") continue;
        std::printf("%-20s %s\n", key.c_str(), jsonText(value).c_str());
    }
    for (const auto& b : n["blobs"]) std::printf("blob %s\n", jsonText(b).c_str());
}

int runInspect(const InspectArgs& a) {
    Database db = Database::open(a.path);
    nlohmann::json out;
    if (a.node) {
        try {
            out = nodeJson(db.skeleton(), *a.node);
        } catch (const std::invalid_argument& e) {  // no such node: the line names the database too
            throw std::invalid_argument(a.path + ": " + e.what());
        }
    } else if (a.tree) {
        out = treeJson(db.skeleton(), a.depth);
    } else {
        out = toJson(summarize(db));
    }
    if (a.json) std::cout << jsonText(out, 2) << '\n';
    else if (a.node) printNode(out);
    else if (a.tree) printTree(out, 0);
    else printSummary(summarize(db));
    return 0;
}

}  // namespace

void addInspect(CLI::App& app, int& status) {
    auto args = std::make_shared<InspectArgs>();
    CLI::App* sub = app.add_subcommand("inspect", "summarise an HLOD database, its tree or one node");
    addDatabaseArgument(*sub, args->path);
    auto* tree = sub->add_flag("--tree", args->tree, "print the node tree");
    sub->add_option("--depth", args->depth, "with --tree: levels to print (0 = all)")->needs(tree)
        ->check(wholeNumber(args->depth));
    sub->add_option("--node", args->node, "print one node in full")->excludes(tree)
        ->check(wholeNumber(args->node));
    sub->add_flag("--json", args->json, "machine-readable JSON output");
    sub->callback([args, &status] { status = runGuarded("inspect", [&] { return runInspect(*args); }); });
}

}  // namespace hlod::cli
