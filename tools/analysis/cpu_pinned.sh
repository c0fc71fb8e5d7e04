#!/usr/bin/env bash
# Single-thread processes pinned to CPU 0 and to CPU 1, and a 2-thread process, round after round for SECS seconds,
# each with the cache-line round trip between the two CPUs (core_probe.cpp) before it: whether a slow process needs
# two threads (data crossing between CPUs) or shows on one CPU alone, and whether MODE_SGBM_3WAY in the same process
# shares it. Each process: lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --timing 3 (SDSGM, 8 paths).
#   tools/analysis/cpu_pinned.sh SECS [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90]
# ASLR=off in the environment runs every process under `setarch -R` (no address-space randomisation).
set -eo pipefail
cd "$(dirname "$0")/../.."
SECS=${1:?seconds}
T=${2:-$HOME/.cache/lidarsgm/build-cuda90}/bin/lidarsgm_fuse
NORAND=; [ "${ASLR:-on}" = off ] && NORAND="setarch -R"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/main.cpp" <<'EOF'
#include <cstdio>
extern "C" double roundTripNs(int trips);
int main() { std::printf("%.0f\n", roundTripNs(200000)); }
EOF
g++ -O2 tools/analysis/core_probe.cpp "$tmp/main.cpp" -o "$tmp/rtt" -lpthread
run() {   # prints "SDSGM_ms 3WAY_ms"
  ${NORAND} "$@" "$T" --kitti-frame testdata/kitti --id 000002 --timing 3 --threads "${THREADS:-1}" | awk -F'|' '
    /lidarsgm SDSGM/ { gsub(/[ ms]/, "", $3); s = $3 } /MODE_SGBM_3WAY/ { gsub(/[ ms]/, "", $3); w = $3 }
    END { print s, w }'
}
echo "# $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) CPUs ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
echo "# Command: ${NORAND:+ASLR=off }tools/analysis/cpu_pinned.sh $SECS; columns: round trip (ns), then SDSGM / MODE_SGBM_3WAY medians (ms)"
end=$((SECONDS + SECS))
while [ $SECONDS -lt $end ]; do
  r=$("$tmp/rtt"); a=$(run taskset -c 0); b=$(run taskset -c 1); c=$(THREADS=2 run env)
  echo "rtt $r | CPU 0, 1 thread: $a | CPU 1, 1 thread: $b | 2 threads: $c"
done | tee "$tmp/log"
awk -F'|' '{ for (i = 2; i <= 3; i++) { split($i, a, ":"); split(a[2], t, " "); print t[1], t[2] } }' "$tmp/log" |
  sort -g | awk '{ s[NR] = $1; w[NR] = $2; if (NR == 1 || $2 < wmin) wmin = $2; if ($2 > wmax) wmax = $2 }
    END { fast = s[1]; slow = 0; alone = 0
          for (i = 1; i <= NR; i++) if (s[i] > 1.15 * fast) { slow++; if (w[i] < 1.1 * wmin) alone++ }
          printf "%d single-thread processes: SDSGM %.1f-%.1f ms, MODE_SGBM_3WAY %.1f-%.1f ms; %d SDSGM more than 15 %% above the fastest, in %d of them MODE_SGBM_3WAY within 10 %% of its fastest\n",
                 NR, s[1], s[NR], wmin, wmax, slow, alone }'
