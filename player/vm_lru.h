// The replacement policy of Varadhan & Manocha 2002 §4.3 (Fig. 7): the in-core nodes in a doubly
// linked InMemoryList; at the start of a frame's fetch the tail is remembered (StartTail); every
// node accessed afterwards (fetched, prefetched, or found in memory) moves immediately after
// StartTail, so that the accessed nodes lie beyond it in the reverse of their access order;
// replacement victims are taken from the head.
#pragma once

#include <cstdint>
#include <vector>

namespace hlod {

class InMemoryList {
public:
    explicit InMemoryList(uint32_t nodeCount);
    void markStartTail();      // step 1: StartTail = tail
    void access(uint32_t id);  // step 2: move (or insert) it immediately after StartTail
    void remove(uint32_t id);
    bool contains(uint32_t id) const { return in_[id] != 0; }
    uint32_t head() const { return head_; }
    uint32_t next(uint32_t id) const { return next_[id]; }
    uint32_t startTail() const { return startTail_; }
    std::vector<uint32_t> order() const;  // head to tail

private:
    std::vector<uint32_t> prev_, next_;
    std::vector<uint8_t> in_;
    uint32_t head_, tail_, startTail_;
    void unlink(uint32_t id);
};

}  // namespace hlod
