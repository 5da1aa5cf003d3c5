// The priority queue of thesis §4.3 (linked list + hash + cached highest unloaded node) and the
// heap alternative, checked against a brute-force reference under random update streams.
#include "player/priority_queue.h"
#include "tests/support/heap_queue.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

using namespace hlod;

namespace {

// A node's loaded flag belongs to the node, not to its place in the queue: it is kept across
// remove() and set by setLoaded() whether or not the node is queued (thesis §4.3: the queue
// orders nodes, residency is the loader's), so the reference models it for every id.
struct Reference {
    std::map<uint32_t, double> priority;
    std::map<uint32_t, bool> loaded;  // every id ever flagged; absent = not loaded
    double highestUnloaded() const {
        double best = -1;
        for (auto& [id, p] : priority)
            if (!isLoaded(id)) best = std::max(best, p);
        return best;
    }
    double lowestLoaded() const {
        double best = 1e300;
        for (auto& [id, p] : priority)
            if (isLoaded(id)) best = std::min(best, p);
        return best;
    }
    bool isLoaded(uint32_t id) const { return loaded.count(id) && loaded.at(id); }
};

template <class Queue>
void randomStream(bool coherent, uint32_t seed) {
    const uint32_t n = 300;
    Queue q(n);
    Reference ref;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<uint32_t> pick(0, n - 1), op(0, 9);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<double> base(n);
    for (double& b : base) b = unit(rng) * 100;
    for (int step = 0; step < 20000; ++step) {
        uint32_t id = pick(rng);
        uint32_t o = op(rng);
        if (o < 6) {  // coherent: small moves; otherwise arbitrary (ties included)
            double p = coherent ? base[id] * (0.95 + 0.1 * unit(rng)) : double(pick(rng) % 50);
            base[id] = coherent ? p : base[id];
            q.update(id, p);
            ref.priority[id] = p;
        } else if (o < 8) {
            bool l = unit(rng) < 0.5;
            q.setLoaded(id, l);
            ref.loaded[id] = l;
        } else {
            q.remove(id);
            ref.priority.erase(id);
        }
        ASSERT_EQ(q.loaded(id), ref.isLoaded(id)) << step;
        ASSERT_EQ(q.size(), ref.priority.size());
        uint32_t hu = q.highestUnloaded();
        double want = ref.highestUnloaded();
        if (want < 0) {
            ASSERT_EQ(hu, kNoNode) << step;
        } else {
            ASSERT_NE(hu, kNoNode) << step;
            ASSERT_EQ(q.priority(hu), want) << step;
            ASSERT_FALSE(q.loaded(hu));
        }
        uint32_t ll = q.lowestLoaded();
        double low = ref.lowestLoaded();
        if (low == 1e300)
            ASSERT_EQ(ll, kNoNode);
        else
            ASSERT_EQ(q.priority(ll), low) << step;
        if constexpr (std::is_same_v<Queue, LinkedPriorityQueue>) {
            ASSERT_TRUE(q.checkInvariants()) << step;
        }
    }
}

}  // namespace

TEST(LinkedPriorityQueue, MatchesReferenceOnCoherentUpdates) { randomStream<LinkedPriorityQueue>(true, 1); }
TEST(LinkedPriorityQueue, MatchesReferenceOnArbitraryUpdatesWithTies) { randomStream<LinkedPriorityQueue>(false, 2); }
TEST(HeapPriorityQueue, MatchesReferenceOnCoherentUpdates) { randomStream<HeapPriorityQueue>(true, 3); }
TEST(HeapPriorityQueue, MatchesReferenceOnArbitraryUpdatesWithTies) { randomStream<HeapPriorityQueue>(false, 4); }

TEST(LinkedPriorityQueue, KeepsDecreasingOrderAndCachesFirstUnloaded) {
    LinkedPriorityQueue q(5);
    q.update(0, 5);
    q.update(1, 9);
    q.update(2, 1);
    EXPECT_EQ(q.head(), 1u);
    EXPECT_EQ(q.next(1), 0u);
    EXPECT_EQ(q.tail(), 2u);
    EXPECT_EQ(q.highestUnloaded(), 1u);
    q.setLoaded(1, true);
    EXPECT_EQ(q.highestUnloaded(), 0u);
    q.update(2, 7);  // moves above the cached node
    EXPECT_EQ(q.highestUnloaded(), 2u);
    q.update(2, 0.5);  // the cached node moves below another unloaded one
    EXPECT_EQ(q.highestUnloaded(), 0u);
    EXPECT_EQ(q.lowestLoaded(), 1u);
    EXPECT_TRUE(q.checkInvariants());
}
