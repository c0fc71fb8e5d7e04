// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU aggregation's sweeps as a wavefront: a sweep is rows x strips of work items, and a strip takes its next row
// as soon as what that row reads is there, instead of every strip waiting for the whole row before (one barrier per
// row: 2 x 375 at KITTI size, what kept 16 threads at 5 x one thread). A strip's items touch its own columns only,
// apart from a pixel's path costs at each edge, so a thread that keeps to its own strips keeps their data in its
// own core's cache: when the two CPUs of a virtual machine sit far apart (a cache line takes 330 instead of 55 ns
// there and back on the 2-core EPYC, tools/analysis/cpu_drift.py), every row that passes between threads pays for
// it. What a strip's row reads:
//  - its own row before (the strip runs its rows in order, one thread at a time);
//  - with diagonal paths, the last pixel of each neighbouring strip's row before: strips beside each other are at
//    most one row apart, so the path rows kept by row parity (AggregationState::L) are never overwritten early;
//  - in the down sweep (ring > 0), the left-right path at the last pixel of strip s - 1 in the same row; and the
//    ring slot it writes must be free: its own back item of the row `ring` rows before has run. A back item (the
//    right-left path of the strip's row) reads the strip's forward item of the row and the right-left path at the
//    first pixel of strip s + 1 in the same row.
// A task keeps to its own strips while the task they belong to runs: taking a running task's strip when one's own
// are not ready moves that strip's rows to the other core and back (on the 2-core EPYC that stealing made the calls
// 2.5 x slower while the two CPUs sat far apart). The strips of a task that has not started are anyone's, and an
// item never waits inside, so the sweep ends however many of the parallel_for_ tasks run at once (one task alone
// does everything, as in a nested parallel region).

#ifndef LIDARSGM_WAVEFRONT_HPP
#define LIDARSGM_WAVEFRONT_HPP

#include <atomic>
#include <thread>
#include <vector>

namespace cv { namespace lidarsgm { namespace detail {

class Wavefront
{
public:
    /** strips x rows forward items (rows in sweep order); diagonal: strip s's row i waits for s - 1 and s + 1 to
    finish row i - 1; ring > 0: as many back items, and the hand-offs and ring slots above. */
    Wavefront(int strips, int rows, bool diagonal, int ring)
        : strips_(strips), rows_(rows), diagonal_(diagonal), ring_(ring), state_(strips)
    {
        for (Strip& s : state_)
        {
            s.forward.store(0);
            s.back.store(ring > 0 ? 0 : rows);
            s.busy.store(0);
        }
        failed_.store(false);
    }

    /** Runs the items on up to `threads` threads: forward(s, i) and back(s, i) for strip s and row i. Thread t keeps
    to its strips [t * strips / threads, (t + 1) * strips / threads): of them a ready back item first (it frees a
    ring slot), else the forward item of the one furthest behind, so that the rows and the hand-offs stream in
    order. */
    template <typename Forward, typename Back>
    void run(int threads, const Forward& forward, const Back& back)
    {
        started_ = std::vector<std::atomic<bool> >(threads);
        for (std::atomic<bool>& b : started_)
            b.store(false);
        parallel_for_(Range(0, threads), [&](const Range& r) {
            for (int t = r.start; t < r.end; t++)
            {
                started_[t].store(true);
                work(t, forward, back);
            }
        }, threads);
    }

private:
    struct Strip
    {
        std::atomic<int> forward;   // forward rows finished
        std::atomic<int> back;      // back rows finished (rows where there are none)
        std::atomic<int> busy;      // a thread runs one of its items
        char pad[64 - 3 * sizeof(std::atomic<int>)];   // one strip per cache line: their counters change often
    };

    //! Task t's strips: [first(t), first(t + 1)).
    int first(int t) const
    {
        return t * strips_ / (int)started_.size();
    }

    template <typename Forward, typename Back>
    void work(int task, const Forward& forward, const Back& back)
    {
        try
        {
            for (int idle = 0; !failed_.load(std::memory_order_relaxed);)
            {
                if (takeOwn(first(task), first(task + 1), forward, back) || takeUnstarted(forward, back))
                    idle = 0;
                else if (finished())
                    break;
                else if (++idle > 64)
                    std::this_thread::yield();   // nothing ready: the items in progress belong to other threads
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
            if (st.back.load(std::memory_order_acquire) < rows_ || st.forward.load(std::memory_order_acquire) < rows_)
                return false;
        return true;
    }

    int done(int s, bool back) const
    {
        return (back ? state_[s].back : state_[s].forward).load(std::memory_order_acquire);
    }

    bool forwardReady(int s, int i) const
    {
        if (i >= rows_)
            return false;
        if (s > 0 && ((ring_ > 0 && done(s - 1, false) <= i) || (diagonal_ && done(s - 1, false) < i)))
            return false;
        if (diagonal_ && s + 1 < strips_ && done(s + 1, false) < i)
            return false;
        return ring_ == 0 || i < ring_ || done(s, true) > i - ring_;
    }

    bool backReady(int s, int i) const
    {
        return ring_ > 0 && i < rows_ && done(s, false) > i && (s + 1 == strips_ || done(s + 1, true) > i);
    }

    //! Among strips [s0, s1): a ready back item, else the forward item of the strip furthest behind; runs it.
    template <typename Forward, typename Back>
    bool takeOwn(int s0, int s1, const Forward& forward, const Back& back)
    {
        int best = -1, bestRow = rows_;
        for (int s = s0; s < s1; s++)
        {
            const Strip& st = state_[s];
            if (st.busy.load(std::memory_order_relaxed))
                continue;
            if (backReady(s, st.back.load(std::memory_order_relaxed)) && runItem(s, forward, back))
                return true;
            const int i = st.forward.load(std::memory_order_relaxed);
            if (i < bestRow && forwardReady(s, i))
            {
                best = s;
                bestRow = i;
            }
        }
        return best >= 0 && runItem(best, forward, back);
    }

    //! A ready item of a task that has not started (a task's own have started).
    template <typename Forward, typename Back>
    bool takeUnstarted(const Forward& forward, const Back& back)
    {
        for (int t = 0; t < (int)started_.size(); t++)
            if (!started_[t].load(std::memory_order_relaxed))
                for (int s = first(t); s < first(t + 1); s++)
                    if (runItem(s, forward, back))
                        return true;
        return false;
    }

    //! Runs strip s's next back item, else its next forward item, if one is ready and no other thread holds the strip.
    template <typename Forward, typename Back>
    bool runItem(int s, const Forward& forward, const Back& back)
    {
        Strip& st = state_[s];
        if (st.busy.load(std::memory_order_relaxed) || st.busy.exchange(1, std::memory_order_acquire))
            return false;
        bool ran = true;
        const int b = st.back.load(std::memory_order_relaxed), f = st.forward.load(std::memory_order_relaxed);
        if (backReady(s, b))   // only the holder of busy moves the counters
        {
            back(s, b);
            st.back.store(b + 1, std::memory_order_release);
        }
        else if (forwardReady(s, f))
        {
            forward(s, f);
            st.forward.store(f + 1, std::memory_order_release);
        }
        else
            ran = false;
        st.busy.store(0, std::memory_order_release);
        return ran;
    }

    const int strips_, rows_;
    const bool diagonal_;
    const int ring_;
    std::vector<Strip> state_;
    std::vector<std::atomic<bool> > started_;    // per task
    std::atomic<bool> failed_;
};

}}} // namespace cv::lidarsgm::detail

#endif
