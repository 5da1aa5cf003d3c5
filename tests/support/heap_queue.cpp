// Benchmark baseline (heap_queue.h): two indexed binary heaps, O(log n) per operation.
#include "tests/support/heap_queue.h"

#include <utility>

namespace hlod {

HeapPriorityQueue::HeapPriorityQueue(uint32_t nodeCount)
    : priority_(nodeCount, 0), loaded_(nodeCount, 0), where_(nodeCount) {}

bool HeapPriorityQueue::above(int h, uint32_t a, uint32_t b) const {
    return h == 0 ? priority_[a] > priority_[b] : priority_[a] < priority_[b];
}

void HeapPriorityQueue::place(int h, uint32_t index, uint32_t id) {
    heap_[h][index] = id;
    where_[id] = {uint8_t(h), index};
}

void HeapPriorityQueue::siftUp(int h, uint32_t index) {
    auto& heap = heap_[h];
    uint32_t id = heap[index];
    while (index > 0) {
        uint32_t parent = (index - 1) / 2;
        if (!above(h, id, heap[parent])) break;
        place(h, index, heap[parent]);
        index = parent;
    }
    place(h, index, id);
}

void HeapPriorityQueue::siftDown(int h, uint32_t index) {
    auto& heap = heap_[h];
    uint32_t id = heap[index], n = uint32_t(heap.size());
    for (;;) {
        uint32_t child = 2 * index + 1;
        if (child >= n) break;
        if (child + 1 < n && above(h, heap[child + 1], heap[child])) ++child;
        if (!above(h, heap[child], id)) break;
        place(h, index, heap[child]);
        index = child;
    }
    place(h, index, id);
}

void HeapPriorityQueue::insert(int h, uint32_t id) {
    heap_[h].push_back(id);
    siftUp(h, uint32_t(heap_[h].size() - 1));
}

void HeapPriorityQueue::erase(uint32_t id) {
    Where w = where_[id];
    auto& heap = heap_[w.heap];
    uint32_t last = heap.back();
    heap.pop_back();
    where_[id] = {};
    if (last == id) return;
    place(w.heap, w.index, last);
    siftUp(w.heap, w.index);
    siftDown(w.heap, where_[last].index);
}

void HeapPriorityQueue::update(uint32_t id, double priority) {
    priority_[id] = priority;
    if (!contains(id)) return insert(loaded_[id] ? 1 : 0, id);
    Where w = where_[id];
    siftUp(w.heap, w.index);
    siftDown(w.heap, where_[id].index);
}

void HeapPriorityQueue::remove(uint32_t id) {
    if (contains(id)) erase(id);
}

void HeapPriorityQueue::setLoaded(uint32_t id, bool loaded) {
    if (bool(loaded_[id]) == loaded) return;
    loaded_[id] = loaded;
    if (!contains(id)) return;
    erase(id);
    insert(loaded ? 1 : 0, id);
}

}  // namespace hlod
