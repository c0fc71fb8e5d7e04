// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU aggregation's sweeps as a wavefront: a sweep is rows x strips of work items, and a strip takes its next row
// as soon as what that row reads is there, instead of every strip waiting for the whole row before (one barrier per
// row: 2 x 375 at KITTI size, what kept 16 threads at 5 x one thread). What a strip's row reads:
//  - its own row before (the strip runs its rows in order, one thread at a time);
//  - with diagonal paths, the last pixel of each neighbouring strip's row before: strips beside each other are
//    at most one row apart, so the path rows kept by row parity (AggregationState::L) are never overwritten early;
//  - with a ring of cost rows (the down sweep), the slot it writes must be free: the row ring rows before has had its
//    horizontal paths.
// The horizontal paths of a row are items too, ready once every strip has done the row; they are the longest items
// and go first. Any thread takes any ready item and an item never waits inside, so the sweep ends however many of
// the parallel_for_ tasks run at once (one task alone does everything, as in a nested parallel region).

#ifndef LIDARSGM_WAVEFRONT_HPP
#define LIDARSGM_WAVEFRONT_HPP

#include <atomic>
#include <thread>

namespace cv { namespace lidarsgm { namespace detail {

class Wavefront
{
public:
    /** strips x rows items (rows in sweep order); neighbours: strip s waits for s - 1 and s + 1 to finish its row
    before; ringRows > 0: a horizontal item per row, and strip row i waits for horizontal item i - ringRows. */
    Wavefront(int strips, int rows, bool neighbours, int ringRows)
        : strips_(strips), rows_(rows), neighbours_(neighbours), ring_(ringRows),
          state_(strips), rowCount_(ringRows > 0 ? rows : 0), rowDone_(ringRows > 0 ? rows : 0)
    {
        for (Strip& s : state_)
        {
            s.done.store(0);
            s.busy.store(0);
        }
        for (int i = 0; i < (int)rowCount_.size(); i++)
        {
            rowCount_[i].store(0);
            rowDone_[i].store(0);
        }
        rowsFinished_.store(0);
        nextRow_.store(0);
        failed_.store(false);
    }

    /** Runs the items on up to `threads` threads: stripRow(s, i) for strip s and row i, horizontal(i, t) for row i on
    task t < threads (no two tasks share a t: scratch buffers can be per task).
    Thread t keeps to its own strips [t * strips / threads, (t + 1) * strips / threads) while one of them is ready
    (their path rows stay in its core's cache) and takes any other ready item otherwise. */
    template <typename StripRow, typename Horizontal>
    void run(int threads, const StripRow& stripRow, const Horizontal& horizontal)
    {
        parallel_for_(Range(0, threads), [&](const Range& r) {
            for (int t = r.start; t < r.end; t++)
                work(t, t * strips_ / threads, (t + 1) * strips_ / threads, stripRow, horizontal);
        }, threads);
    }

private:
    struct Strip
    {
        std::atomic<int> done;   // rows finished
        std::atomic<int> busy;   // a thread runs its next row
        char pad[64 - 2 * sizeof(std::atomic<int>)];   // one strip per cache line: their counters change often
    };

    template <typename StripRow, typename Horizontal>
    void work(int task, int home0, int home1, const StripRow& stripRow, const Horizontal& horizontal)
    {
        try
        {
            for (int idle = 0; !failed_.load(std::memory_order_relaxed);)
            {
                if (takeHorizontal(task, horizontal) || takeStrip(home0, home1, stripRow))
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
        if (ring_ > 0)
            return rowsFinished_.load(std::memory_order_acquire) == rows_;   // a row's horizontal item comes last
        for (const Strip& st : state_)
            if (st.done.load(std::memory_order_acquire) < rows_)
                return false;
        return true;
    }

    template <typename Horizontal>
    bool takeHorizontal(int task, const Horizontal& horizontal)
    {
        if (ring_ == 0)
            return false;
        int i = nextRow_.load(std::memory_order_relaxed);
        if (i >= rows_ || rowCount_[i].load(std::memory_order_acquire) < strips_ ||
            !nextRow_.compare_exchange_strong(i, i + 1))
            return false;
        horizontal(i, task);
        rowDone_[i].store(1, std::memory_order_release);
        rowsFinished_.fetch_add(1, std::memory_order_acq_rel);
        return true;
    }

    bool ready(int s, int i) const
    {
        if (i >= rows_)
            return false;
        if (neighbours_ && ((s > 0 && state_[s - 1].done.load(std::memory_order_acquire) < i) ||
                            (s + 1 < strips_ && state_[s + 1].done.load(std::memory_order_acquire) < i)))
            return false;
        return ring_ == 0 || i < ring_ || rowDone_[i - ring_].load(std::memory_order_acquire) != 0;
    }

    /** Runs the next row of a ready strip: among the thread's own the one furthest behind (so that rows complete in
    order and the horizontal items and ring slots follow), else the first ready one of the others. */
    template <typename StripRow>
    bool takeStrip(int home0, int home1, const StripRow& stripRow)
    {
        int best = -1, bestRow = rows_;
        for (int s = home0; s < home1; s++)
        {
            const Strip& st = state_[s];
            const int i = st.done.load(std::memory_order_relaxed);
            if (i < bestRow && !st.busy.load(std::memory_order_relaxed) && ready(s, i))
            {
                best = s;
                bestRow = i;
            }
        }
        if (best >= 0 && runStrip(best, stripRow))
            return true;
        for (int k = 0; k < strips_ - (home1 - home0); k++)
            if (runStrip((home1 + k) % strips_, stripRow))
                return true;
        return false;
    }

    //! Runs strip s's next row if it is ready and no other thread holds the strip.
    template <typename StripRow>
    bool runStrip(int s, const StripRow& stripRow)
    {
        Strip& st = state_[s];
        if (st.busy.load(std::memory_order_relaxed) || !ready(s, st.done.load(std::memory_order_relaxed)))
            return false;
        if (st.busy.exchange(1, std::memory_order_acquire))
            return false;
        const int i = st.done.load(std::memory_order_relaxed);   // only the holder of busy moves it
        if (!ready(s, i))
        {
            st.busy.store(0, std::memory_order_release);
            return false;
        }
        stripRow(s, i);
        st.done.store(i + 1, std::memory_order_release);
        st.busy.store(0, std::memory_order_release);
        if (ring_ > 0)
            rowCount_[i].fetch_add(1, std::memory_order_acq_rel);
        return true;
    }

    const int strips_, rows_;
    const bool neighbours_;
    const int ring_;
    std::vector<Strip> state_;
    std::vector<std::atomic<int>> rowCount_;   // strips done per row (rows with horizontal items)
    std::vector<std::atomic<int>> rowDone_;    // the row's horizontal item done
    std::atomic<int> rowsFinished_;            // horizontal items done
    std::atomic<int> nextRow_;                 // the next horizontal item to take
    std::atomic<bool> failed_;
};

}}} // namespace cv::lidarsgm::detail

#endif
