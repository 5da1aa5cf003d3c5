// The loading thread's priority queue (thesis §4.3): a doubly linked list kept in decreasing
// priority, a hash from node ID to list entry, incremental moves for the small frame-to-frame
// priority changes, and a cached pointer to the highest-priority unloaded node. The binary-heap
// baseline it is benchmarked against is a test fixture (tests/support/heap_queue.h).
#pragma once

#include <cstdint>
#include <vector>

namespace hlod {

inline constexpr uint32_t kNoNode = 0xFFFFFFFFu;

class LinkedPriorityQueue {
public:
    explicit LinkedPriorityQueue(uint32_t nodeCount);

    // Inserts the node or moves it to its new place (walking from where it was: O(1) when
    // the priority changed little, as between two frames).
    void update(uint32_t id, double priority);
    void remove(uint32_t id);
    void setLoaded(uint32_t id, bool loaded);

    bool contains(uint32_t id) const { return slot_[id].inList; }
    double priority(uint32_t id) const { return slot_[id].priority; }
    bool loaded(uint32_t id) const { return slot_[id].loaded; }
    uint32_t size() const { return size_; }

    uint32_t highestUnloaded() const { return firstUnloaded_; }  // kNoNode when none
    uint32_t lowestLoaded() const;                               // kNoNode when none
    uint32_t head() const { return head_; }
    uint32_t tail() const { return tail_; }
    uint32_t next(uint32_t id) const { return slot_[id].next; }
    uint32_t prev(uint32_t id) const { return slot_[id].prev; }

    bool checkInvariants() const;  // order, links, size and the cache (for tests)

private:
    struct Slot {
        double priority = 0;
        uint32_t prev = kNoNode, next = kNoNode;
        bool inList = false, loaded = false;
    };
    // Node IDs are dense (id == index in the skeleton), so the thesis's hash table from the
    // unique ID is the identity into this vector.
    std::vector<Slot> slot_;
    uint32_t head_ = kNoNode, tail_ = kNoNode, size_ = 0;
    uint32_t firstUnloaded_ = kNoNode;

    void unlink(uint32_t id);
    void linkBefore(uint32_t id, uint32_t before);  // before == kNoNode: append
    uint32_t placeFrom(uint32_t id, uint32_t start);  // entry to insert before, searching from start
    void refreshCacheFrom(uint32_t start);
    void noteMaybeFirstUnloaded(uint32_t id);
};

}  // namespace hlod
