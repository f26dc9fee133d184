// AllocationCounter: every form of operator new is counted, on the calling thread and in
// the all-threads total, and code that does not allocate counts nothing. The zero-count
// tests of the streaming containers rely on this to not pass vacuously.
#include "AllocationCounter.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <new>
#include <thread>
#include <vector>

namespace terrain::test {
namespace {

// A volatile pointer escapes the optimiser: a new/delete pair whose result is only ever
// stored here cannot be elided (C++14 allows eliding unobserved allocations).
template <typename T>
void keep(T* pointer) {
    T* volatile sink = pointer;
    static_cast<void>(sink);
}

struct alignas(64) CacheLine {
    std::uint8_t bytes[64];
};

TEST(AllocationCounter, CountsAnIntentionalNew) {
    const AllocationScope scope;
    int* value = new int(7);
    keep(value);
    delete value;
    EXPECT_EQ(scope.allocations(), 1u);
    EXPECT_GE(scope.allocationsAllThreads(), 1u);
}

TEST(AllocationCounter, CountsEveryFormOfNew) {
    const AllocationScope scope;
    int* array = new int[3];
    keep(array);
    delete[] array;
    int* nothrowValue = new (std::nothrow) int(1);
    keep(nothrowValue);
    delete nothrowValue;
    int* nothrowArray = new (std::nothrow) int[5];
    keep(nothrowArray);
    delete[] nothrowArray;
    auto* aligned = new CacheLine;  // over-aligned: the align_val_t forms
    keep(aligned);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned) % alignof(CacheLine), 0u);
    delete aligned;
    auto* alignedArray = new CacheLine[3];
    keep(alignedArray);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(alignedArray) % alignof(CacheLine), 0u);
    delete[] alignedArray;
    auto* alignedNothrow = new (std::nothrow) CacheLine;
    keep(alignedNothrow);
    delete alignedNothrow;
    EXPECT_EQ(scope.allocations(), 6u);
}

TEST(AllocationCounter, CountsContainerGrowthButNotReuse) {
    std::vector<int> values;
    {
        const AllocationScope scope;
        values.reserve(16);
        EXPECT_EQ(scope.allocations(), 1u);
    }
    const AllocationScope scope;
    for (int i = 0; i < 16; ++i) values.push_back(i);  // within the capacity
    values.clear();
    for (int i = 0; i < 16; ++i) values.push_back(i);
    EXPECT_EQ(scope.allocations(), 0u);
}

TEST(AllocationCounter, OtherThreadsCountOnlyInTheAllThreadsTotal) {
    std::atomic<bool> go{false};
    std::atomic<std::uint64_t> workerCount{0};
    std::thread worker([&] {
        while (!go.load()) std::this_thread::yield();
        const AllocationScope workerScope;
        for (int i = 0; i < 3; ++i) {
            int* value = new int(i);
            keep(value);
            delete value;
        }
        workerCount = workerScope.allocations();
    });
    // Constructed after the thread started: starting it allocates on this thread.
    const AllocationScope scope;
    go = true;
    worker.join();
    EXPECT_EQ(workerCount.load(), 3u);
    EXPECT_EQ(scope.allocations(), 0u);
    EXPECT_GE(scope.allocationsAllThreads(), 3u);
}

}  // namespace
}  // namespace terrain::test
