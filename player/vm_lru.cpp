// Varadhan & Manocha 2002 §4.3, the LRU variant of Fig. 7. Open choice (player/LOADERS.md): when
// the node at StartTail itself is accessed, StartTail moves to its predecessor first, so that the
// node stays where it is (just after the new StartTail) instead of StartTail dangling. With an
// empty list at the mark, "after StartTail" is the head.
#include "player/vm_lru.h"

#include "player/priority_queue.h"

namespace hlod {

InMemoryList::InMemoryList(uint32_t n)
    : prev_(n, kNoNode), next_(n, kNoNode), in_(n, 0), head_(kNoNode), tail_(kNoNode), startTail_(kNoNode) {}

void InMemoryList::markStartTail() { startTail_ = tail_; }

void InMemoryList::unlink(uint32_t id) {
    (prev_[id] == kNoNode ? head_ : next_[prev_[id]]) = next_[id];
    (next_[id] == kNoNode ? tail_ : prev_[next_[id]]) = prev_[id];
    prev_[id] = next_[id] = kNoNode;
    in_[id] = 0;
}

void InMemoryList::remove(uint32_t id) {
    if (!in_[id]) return;
    if (id == startTail_) startTail_ = prev_[id];
    unlink(id);
}

void InMemoryList::access(uint32_t id) {
    remove(id);
    uint32_t after = startTail_;
    uint32_t before = after == kNoNode ? head_ : next_[after];
    prev_[id] = after;
    next_[id] = before;
    (after == kNoNode ? head_ : next_[after]) = id;
    (before == kNoNode ? tail_ : prev_[before]) = id;
    in_[id] = 1;
}

std::vector<uint32_t> InMemoryList::order() const {
    std::vector<uint32_t> out;
    for (uint32_t c = head_; c != kNoNode; c = next_[c]) out.push_back(c);
    return out;
}

}  // namespace hlod
