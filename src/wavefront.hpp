// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU aggregation's sweeps as a wavefront: a sweep is rows x strips of work items, and a strip takes its next row
// as soon as what that row reads is there, instead of every strip waiting for the whole row before (one barrier per
// row: 2 x 375 at KITTI size, which would hold 16 threads to 5 x one thread). A strip's items touch its own columns
// only, apart from a pixel's path costs at each edge, so a thread that keeps to its own strips keeps their data in its
// own core's cache: when the two CPUs of a virtual machine sit far apart (a cache line takes 330 instead of 55 ns
// there and back on the 2-core EPYC; doc/design.md, section 3), every row that passes between threads pays for it.
// What a strip's row reads:
//  - its own row before (the strip runs its rows in order, one thread at a time);
//  - with diagonal paths, the last pixel of each neighbouring strip's row before: strips beside each other are at
//    most one row apart, so the path records that a row overwrites in place (AggregationState) are never
//    overwritten early;
//  - the horizontal path of the sweep at the edge pixel of the strip it enters from, in the same row (down: the
//    left-right path, from strip s - 1; up: the right-left path, from strip s + 1), kept in a ring of `ring` rows:
//    a strip starts a row only when the strip that reads its hand-off has taken the one `ring` rows before.
// A task keeps to its own strips while the task they belong to runs: taking a running task's strip when one's own
// are not ready moves that strip's rows to the other core and back (on the 2-core EPYC stealing makes the calls
// 2.5 x slower while the two CPUs sit far apart). The strips of a task that has not started are anyone's, and an
// item never waits inside, so the sweep ends however many of the parallel_for_ tasks run at once (one task alone
// does everything, as in a nested parallel region).

#ifndef LIDARSGM_WAVEFRONT_HPP
#define LIDARSGM_WAVEFRONT_HPP

#include <algorithm>
#include <atomic>
#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif
#include <thread>
#include <vector>

namespace cv { namespace lidarsgm { namespace detail {

class Wavefront
{
public:
    /** strips x rows items (rows in sweep order); diagonal: strip s's row i waits for s - 1 and s + 1 to finish row
    i - 1; from: -1 (+1) strip s's row i reads strip s - 1's (s + 1's) row i, kept in a ring of `ring` rows; 0: no
    hand-off. */
    Wavefront(int strips, int rows, bool diagonal, int from, int ring)
        : strips_(strips), rows_(rows), diagonal_(diagonal), from_(from), ring_(std::max(ring, 1)), state_(strips)
    {
        for (Strip& s : state_)
        {
            s.done.store(0);
            s.busy.store(0);
        }
        failed_.store(false);
    }

    /** Runs item(s, i) for strip s and row i on up to `threads` threads. Thread t keeps to its strips [t * strips /
    threads, (t + 1) * strips / threads), taking the ready row of the one furthest behind, so that the rows and the
    hand-offs stream in order. */
    template <typename Item>
    void run(int threads, const Item& item)
    {
        started_ = std::vector<std::atomic<bool> >(threads);
        for (std::atomic<bool>& b : started_)
            b.store(false);
        parallel_for_(Range(0, threads), [&](const Range& r) {
            for (int t = r.start; t < r.end; t++)
            {
                started_[t].store(true);
                work(t, item);
            }
        }, threads);
    }

private:
    /* Idle rounds before a waiting thread yields its CPU: a round takes well under a microsecond, a strip's row tens
    of microseconds, and a yield costs a system call (and on a virtual machine its CPU may not come back soon). */
    enum { SPINS = 4096 };

    static void pause()
    {
#if defined(__SSE2__) || defined(_M_X64)
        _mm_pause();
#elif defined(__aarch64__) && (defined(__GNUC__) || defined(__clang__))
        __asm__ __volatile__("yield");
#endif
    }

    struct Strip
    {
        std::atomic<int> done;      // rows finished
        std::atomic<int> busy;      // a thread runs one of its items
        char pad[64 - 2 * sizeof(std::atomic<int>)];   // one strip per cache line: their counters change often
    };

    //! Task t's strips: [first(t), first(t + 1)).
    int first(int t) const
    {
        return t * strips_ / (int)started_.size();
    }

    template <typename Item>
    void work(int task, const Item& item)
    {
        try
        {
            for (int idle = 0; !failed_.load(std::memory_order_relaxed);)
            {
                if (takeOwn(first(task), first(task + 1), item) || takeUnstarted(item))
                    idle = 0;
                else if (finished())
                    break;
                else if (++idle > SPINS)
                    std::this_thread::yield();   // nothing ready for long: let the system run something else
                else
                    pause();   // nothing ready: the items in progress belong to other threads
            }
        }
        catch (...)
        {
            failed_.store(true);   // the others stop instead of waiting for this thread's items
            throw;
        }
    }

    bool finished() const
    {
        for (const Strip& st : state_)
            if (st.done.load(std::memory_order_acquire) < rows_)
                return false;
        return true;
    }

    int done(int s) const
    {
        return state_[s].done.load(std::memory_order_acquire);
    }

    bool ready(int s, int i) const
    {
        if (i >= rows_)
            return false;
        if (diagonal_ && ((s > 0 && done(s - 1) < i) || (s + 1 < strips_ && done(s + 1) < i)))
            return false;
        if (from_ != 0)
        {
            const int producer = s + from_, consumer = s - from_;
            if (producer >= 0 && producer < strips_ && done(producer) <= i)
                return false;
            if (consumer >= 0 && consumer < strips_ && i >= ring_ && done(consumer) <= i - ring_)
                return false;
        }
        return true;
    }

    //! Among strips [s0, s1): the ready row of the strip furthest behind; runs it.
    template <typename Item>
    bool takeOwn(int s0, int s1, const Item& item)
    {
        int best = -1, bestRow = rows_;
        for (int s = s0; s < s1; s++)
        {
            const Strip& st = state_[s];
            if (st.busy.load(std::memory_order_relaxed))
                continue;
            const int i = st.done.load(std::memory_order_relaxed);
            if (i < bestRow && ready(s, i))
            {
                best = s;
                bestRow = i;
            }
        }
        return best >= 0 && runItem(best, item);
    }

    //! A ready item of a task that has not started (a task's own have started).
    template <typename Item>
    bool takeUnstarted(const Item& item)
    {
        for (int t = 0; t < (int)started_.size(); t++)
            if (!started_[t].load(std::memory_order_relaxed))
                for (int s = first(t); s < first(t + 1); s++)
                    if (runItem(s, item))
                        return true;
        return false;
    }

    //! Runs strip s's next row if it is ready and no other thread holds the strip.
    template <typename Item>
    bool runItem(int s, const Item& item)
    {
        Strip& st = state_[s];
        if (st.busy.load(std::memory_order_relaxed) || st.busy.exchange(1, std::memory_order_acquire))
            return false;
        const int i = st.done.load(std::memory_order_relaxed);   // only the holder of busy moves the counter
        const bool ran = ready(s, i);
        if (ran)
        {
            item(s, i);
            st.done.store(i + 1, std::memory_order_release);
        }
        st.busy.store(0, std::memory_order_release);
        return ran;
    }

    const int strips_, rows_;
    const bool diagonal_;
    const int from_, ring_;
    std::vector<Strip> state_;
    std::vector<std::atomic<bool> > started_;    // per task
    std::atomic<bool> failed_;
};

}}} // namespace cv::lidarsgm::detail

#endif
