// AllocationCounter: counts heap allocations, so tests can prove that steady-state code
// allocates nothing. Link terrain_test_allocation_counter to get it: that library replaces
// the global operator new / delete family for the whole executable, which is why it is
// separate from terrain_test_support and linked only by the tests that use it.
#pragma once

#include <cstdint>

namespace terrain::test {

/// Calls of any replaceable operator new (plain, array, aligned, nothrow) since start-up,
/// by every thread. Deallocations are not counted: freeing is never the problem.
std::uint64_t allocationCountAllThreads();

/// The same, made by the calling thread only; other threads (an I/O thread reading files,
/// GoogleTest's own bookkeeping elsewhere) do not disturb it.
std::uint64_t allocationCountThisThread();

/// Counts the allocations made since construction. Construct it, run the code under test,
/// read allocations() on the same thread, e.g. EXPECT_EQ(scope.allocations(), 0u).
class AllocationScope {
public:
    AllocationScope()
        : m_startThisThread(allocationCountThisThread()),
          m_startAllThreads(allocationCountAllThreads()) {}
    AllocationScope(const AllocationScope&) = delete;
    AllocationScope& operator=(const AllocationScope&) = delete;

    /// Allocations made by the calling thread since construction; call it on the thread
    /// that constructed the scope (thread-local counts of different threads do not compare).
    std::uint64_t allocations() const { return allocationCountThisThread() - m_startThisThread; }

    /// Allocations made by every thread since construction.
    std::uint64_t allocationsAllThreads() const {
        return allocationCountAllThreads() - m_startAllThreads;
    }

private:
    std::uint64_t m_startThisThread;
    std::uint64_t m_startAllThreads;
};

}  // namespace terrain::test
