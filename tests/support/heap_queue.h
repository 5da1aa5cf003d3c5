// Benchmark baseline: the conventional alternative to thesis §4.3's sorted list
// (player/priority_queue.h), two indexed binary heaps with the same interface. Not used by the
// player; bench_queue replays real frame-to-frame update streams into both queues and
// test_player checks it against a reference.
#pragma once

#include "player/priority_queue.h"

#include <cstdint>
#include <vector>

namespace hlod {

// Unloaded nodes by decreasing priority (what to load next) and loaded nodes by increasing
// priority (what to evict). O(log n) for every operation.
class HeapPriorityQueue {
public:
    explicit HeapPriorityQueue(uint32_t nodeCount);
    void update(uint32_t id, double priority);
    void remove(uint32_t id);
    void setLoaded(uint32_t id, bool loaded);
    bool contains(uint32_t id) const { return where_[id].heap != kNone; }
    double priority(uint32_t id) const { return priority_[id]; }
    bool loaded(uint32_t id) const { return loaded_[id]; }
    uint32_t size() const { return uint32_t(heap_[0].size() + heap_[1].size()); }
    uint32_t highestUnloaded() const { return heap_[0].empty() ? kNoNode : heap_[0][0]; }
    uint32_t lowestLoaded() const { return heap_[1].empty() ? kNoNode : heap_[1][0]; }

private:
    static constexpr uint8_t kNone = 2;
    struct Where {
        uint8_t heap = kNone;  // 0 unloaded (max-heap), 1 loaded (min-heap)
        uint32_t index = 0;
    };
    std::vector<double> priority_;
    std::vector<uint8_t> loaded_;
    std::vector<Where> where_;
    std::vector<uint32_t> heap_[2];

    bool above(int h, uint32_t a, uint32_t b) const;
    void place(int h, uint32_t index, uint32_t id);
    void siftUp(int h, uint32_t index);
    void siftDown(int h, uint32_t index);
    void insert(int h, uint32_t id);
    void erase(uint32_t id);
};

}  // namespace hlod
