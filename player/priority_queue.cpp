// Thesis §4.3 "Priority Queue Implementation": a doubly linked list sorted in decreasing
// priority, a hash from node ID, and the cached highest-priority unloaded node. The cache is
// updated when a node moves above it, when it is loaded, removed or moves down; a rescan then
// starts where the cached node was, so the O(N) search is amortised to O(1) per query.
#include "player/priority_queue.h"

namespace hlod {

LinkedPriorityQueue::LinkedPriorityQueue(uint32_t nodeCount) : slot_(nodeCount) {}

void LinkedPriorityQueue::unlink(uint32_t id) {
    Slot& s = slot_[id];
    (s.prev == kNoNode ? head_ : slot_[s.prev].next) = s.next;
    (s.next == kNoNode ? tail_ : slot_[s.next].prev) = s.prev;
    s.prev = s.next = kNoNode;
    s.inList = false;
    --size_;
}

void LinkedPriorityQueue::linkBefore(uint32_t id, uint32_t before) {
    Slot& s = slot_[id];
    s.next = before;
    s.prev = before == kNoNode ? tail_ : slot_[before].prev;
    (s.prev == kNoNode ? head_ : slot_[s.prev].next) = id;
    (before == kNoNode ? tail_ : slot_[before].prev) = id;
    s.inList = true;
    ++size_;
}

// The entry before which `id` belongs, searching from `start` (an entry near its old place,
// or kNoNode for the tail): up while the previous entry has a lower priority, else down.
uint32_t LinkedPriorityQueue::placeFrom(uint32_t id, uint32_t start) {
    double p = slot_[id].priority;
    uint32_t before = start;
    uint32_t above = before == kNoNode ? tail_ : slot_[before].prev;
    while (above != kNoNode && slot_[above].priority < p) {
        before = above;
        above = slot_[above].prev;
    }
    while (before != kNoNode && slot_[before].priority > p) before = slot_[before].next;
    return before;
}

void LinkedPriorityQueue::refreshCacheFrom(uint32_t start) {
    uint32_t c = start;
    while (c != kNoNode && slot_[c].loaded) c = slot_[c].next;
    firstUnloaded_ = c;
}

void LinkedPriorityQueue::noteMaybeFirstUnloaded(uint32_t id) {
    if (slot_[id].loaded) return;
    if (firstUnloaded_ == kNoNode || slot_[id].priority > slot_[firstUnloaded_].priority) {
        firstUnloaded_ = id;
        return;
    }
    // Equal priorities: `id` is above the cache if the cache follows it among equals.
    double p = slot_[id].priority;
    for (uint32_t c = slot_[id].next; c != kNoNode && slot_[c].priority >= p; c = slot_[c].next)
        if (c == firstUnloaded_) {
            firstUnloaded_ = id;
            return;
        }
}

void LinkedPriorityQueue::update(uint32_t id, double priority) {
    Slot& s = slot_[id];
    if (!s.inList) {
        s.priority = priority;
        linkBefore(id, placeFrom(id, kNoNode));  // new nodes usually belong near the tail
        noteMaybeFirstUnloaded(id);
        return;
    }
    bool fits = (s.prev == kNoNode || slot_[s.prev].priority >= priority) &&
                (s.next == kNoNode || slot_[s.next].priority <= priority);
    bool movesDown = priority < s.priority;
    s.priority = priority;
    if (fits) return;
    uint32_t oldNext = s.next;
    unlink(id);
    linkBefore(id, placeFrom(id, oldNext));
    if (id == firstUnloaded_ && movesDown)
        refreshCacheFrom(oldNext);
    else
        noteMaybeFirstUnloaded(id);
}

void LinkedPriorityQueue::remove(uint32_t id) {
    if (!slot_[id].inList) return;
    uint32_t next = slot_[id].next;
    unlink(id);
    if (id == firstUnloaded_) refreshCacheFrom(next);
}

void LinkedPriorityQueue::setLoaded(uint32_t id, bool loaded) {
    Slot& s = slot_[id];
    if (s.loaded == loaded) return;
    s.loaded = loaded;
    if (!s.inList) return;
    if (loaded && id == firstUnloaded_)
        refreshCacheFrom(s.next);
    else if (!loaded)
        noteMaybeFirstUnloaded(id);
}

uint32_t LinkedPriorityQueue::lowestLoaded() const {
    uint32_t c = tail_;
    while (c != kNoNode && !slot_[c].loaded) c = slot_[c].prev;
    return c;
}

bool LinkedPriorityQueue::checkInvariants() const {
    uint32_t count = 0, firstUnloaded = kNoNode, prev = kNoNode;
    for (uint32_t c = head_; c != kNoNode; prev = c, c = slot_[c].next) {
        const Slot& s = slot_[c];
        if (!s.inList || s.prev != prev || ++count > size_) return false;
        if (prev != kNoNode && slot_[prev].priority < s.priority) return false;
        if (firstUnloaded == kNoNode && !s.loaded) firstUnloaded = c;
    }
    return prev == tail_ && count == size_ && firstUnloaded == firstUnloaded_;
}

}  // namespace hlod
