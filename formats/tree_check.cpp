// FORMAT.md §Invariants 1–2, the node tree (thesis §3.3 first-child / next-sibling links): every
// open checks it, so no reader walks a cycle or indexes by an absurd level (before stop 36 a
// crafted cycle hung `hlod stats` and `play` and crashed `export`); `hlod validate` lists every
// violation through the same walk.
#include "formats/db.h"

namespace hlod {

// Walks the root sibling list and every child list; each node may be listed once, so the walk
// is linear even on corrupt links.
void checkTree(const Skeleton& s, const std::function<void(uint32_t node, const std::string& message)>& report) {
    const auto n = uint32_t(s.nodes.size());
    std::vector<uint32_t> rootOfBlock(s.blockCount, kNone);
    std::vector<uint8_t> listed(n, 0);
    std::vector<uint32_t> stack;
    std::vector<uint32_t> roots = s.roots();
    auto list = [&](uint32_t c) {
        if (listed[c]) {
            report(c, "is reached twice through the child/sibling links (a cycle or a shared node)");
            return false;
        }
        listed[c] = 1;
        stack.push_back(c);
        return true;
    };
    for (uint32_t c = roots.empty() ? kNone : roots.front(); c != kNone && list(c); c = s.nodes[c].nextSibling)
        if (s.nodes[c].parent != kNone) report(c, "is in the hlod0 sibling list but has a parent");
    for (uint32_t root : roots) {
        const Node& nd = s.nodes[root];
        if (nd.level != 0) report(root, "has no parent but level " + std::to_string(nd.level) + " (hlod0 is level 0)");
        if (rootOfBlock[nd.block] != kNone) report(root, "is a second root of block " + std::to_string(nd.block));
        else rootOfBlock[nd.block] = root;
    }
    for (uint32_t b = 0; b < s.blockCount; ++b)
        if (rootOfBlock[b] == kNone) report(kNone, "block " + std::to_string(b) + " has no root node");
    while (!stack.empty()) {
        uint32_t id = stack.back();
        stack.pop_back();
        for (uint32_t c = s.nodes[id].firstChild; c != kNone && list(c); c = s.nodes[c].nextSibling)
            if (s.nodes[c].parent != id)
                report(c, "is in the child list of node " + std::to_string(id) + " but its parent is " +
                              (s.nodes[c].parent == kNone ? "none" : std::to_string(s.nodes[c].parent)));
    }
    for (uint32_t i = 0; i < n; ++i) {
        if (!listed[i]) report(i, "is not reachable from the hlod0 list through child/sibling links");
        const Node& nd = s.nodes[i];
        if (nd.parent == kNone) continue;
        const Node& p = s.nodes[nd.parent];
        if (nd.level != p.level + 1)
            report(i, "level " + std::to_string(nd.level) + " is not parent level " + std::to_string(p.level) + " + 1");
        if (nd.block != p.block) report(i, "block " + std::to_string(nd.block) + " differs from its parent's");
    }
}

}  // namespace hlod
