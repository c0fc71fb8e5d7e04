// Cross-core probe for tools/analysis/cpu_drift.py: how long a cache line takes between CPU 0 and CPU 1 and back
// (an atomic passed back and forth), the cost that data one thread writes and another reads pays. In a virtual
// machine it depends on where the host runs the two virtual CPUs at the moment (same core complex or not).
//   g++ -O2 -shared -fPIC tools/analysis/core_probe.cpp -o core_probe.so -lpthread   (cpu_drift.py builds it itself)
#include <atomic>
#include <chrono>
#include <thread>
#include <pthread.h>
#include <sched.h>

static void pinTo(int cpu)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

//! Nanoseconds per round trip of a cache line between CPU 0 and CPU 1, over `trips` round trips (two new threads).
extern "C" double roundTripNs(int trips)
{
    alignas(64) static std::atomic<int> flag;
    flag.store(0);
    double ns = 0;
    std::thread echo([&] {
        pinTo(1);
        for (int i = 0; i < trips; i++)
        {
            while (flag.load(std::memory_order_acquire) != 2 * i + 1) {}
            flag.store(2 * i + 2, std::memory_order_release);
        }
    });
    std::thread ping([&] {
        pinTo(0);
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < trips; i++)
        {
            flag.store(2 * i + 1, std::memory_order_release);
            while (flag.load(std::memory_order_acquire) != 2 * i + 2) {}
        }
        ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / trips;
    });
    ping.join();
    echo.join();
    return ns;
}
