// SIMT emulation (simt.hpp), on the CPU, of the winner-takes-all kernel (wtaKernel, src_cuda/winner_takes_all.cu) in
// two versions of that file (tools/emulate_kernel.sh extracts them into old.inc and new.inc): both take the same random
// sums (the full range's layout or the windows' compact one, costs drawn from a narrow or a wide range so that ties
// and near ties occur), with and without the uniqueness check, the parabola and the non-unique map, and their maps
// (disparities x16 and whole, right-view keys, non-unique winners) are compared value for value.
#include "simt.hpp"
#include "cases.hpp"
#include <array>
#include "cuda_stages.hpp"

#include "versions.hpp"

int main(int argc, char** argv)
{
    CaseRandom U(argc, argv);
    const int seed = U.seed;
    const int W = U(20, 300), H = U(1, 40), D = 16 * U(1, 8), minD = U(0, 3) == 0 ? U(1, 8) : 0;
    const bool windowed = U(0, 1), unique = U(0, 3) != 0, subpixel = U(0, 3) != 0, nonUnique = unique && U(0, 1);
    const int spread = std::array<int, 4>{ 2, 6, 40, 4000 }[U(0, 3)];   // the costs' range above each pixel's floor
    PipelineParams p{};
    p.minDisparity = minD; p.numDisparities = D; p.subpixel = subpixel;
    p.uniqueness1024 = unique ? U(900, 1023) : 1024;
    const int TX = (W + WINDOW_TILE - 1) / WINDOW_TILE, TY = (H + WINDOW_TILE - 1) / WINDOW_TILE;
    std::vector<int> tiles(TX * TY), bases(TX * TY + 1);
    for (int t = 0; t < TX * TY; t++)
    {
        const int lo = windowed ? 16 * U(0, D / 16 - 1) : 0;
        tiles[t] = lo | (windowed ? std::min(D, lo + 16 * U(1, D / 16)) : D) << 16;
        bases[t + 1] = bases[t] + ((tiles[t] >> 16) - (tiles[t] & 0xFFFF)) / WINDOW_ALIGN;
    }
    WindowMap windows{};
    if (windowed)
    {
        windows.tiles = cv::cuda::PtrStepSz<int>(TY, TX, tiles.data(), TX * sizeof(int));
        windows.bases = bases.data();
    }
    // The sums, and each pixel's window.
    const size_t shorts = windowed ? windowVolumeShorts(bases[TX * TY]) : (size_t)W * D * H;
    std::vector<unsigned> vol((shorts + 1) / 2 + 8, 0xFFFFFFFFu);
    ushort* const s16 = (ushort*)vol.data();
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
        {
            const int w = tiles[y / WINDOW_TILE * TX + x / WINDOW_TILE], lo = w & 0xFFFF, hi = w >> 16;
            const int base = bases[y / WINDOW_TILE * TX + x / WINDOW_TILE];
            ushort* s = windowed ? s16 + 2 * windowPairOffset(base, x, y, lo, hi) : s16 + ((size_t)y * W + x) * D + lo;
            // A floor with noise, a dip at the winner (often at a chunk's end) and, for most pixels, a rival dip
            // 1, 2, 3 or more disparities away, up to an eighth above it: the uniqueness check decides both ways.
            const int floor = U(1000, 20000), n = hi - lo;
            for (int d = 0; d < n; d++)
                s[d] = (ushort)(floor + U(0, spread));
            const int c = U(0, 1) ? 16 * U(0, n / 16 - 1) + std::array<int, 4>{ 0, 1, 14, 15 }[U(0, 3)] : U(0, n - 1);
            const int depth = U(floor / 16, floor / 4);
            s[c] = (ushort)(floor - depth);
            if (U(0, 3) != 0)
            {
                const int k = U(0, 1) ? U(1, 3) : U(1, n - 1), r = U(0, 1) ? c + k : c - k;
                if (r >= 0 && r < n)
                    s[r] = (ushort)(floor - depth + U(0, 3) * U(0, (floor - depth) / 24));
            }
        }
    cv::cuda::PtrStepSz<ushort> sum(H, W * D, s16, W * D * sizeof(ushort));
    std::vector<short> maps[2][4];
    std::vector<int> keys[2];
    for (int v = 0; v < 2; v++)
    {
        for (auto& m : maps[v]) m.assign((size_t)W * H, 12345);
        keys[v].assign((size_t)W * H, -1);
        const auto at = [&](std::vector<short>& m) { return cv::cuda::PtrStepSz<short>(H, W, m.data(), W * 2); };
        cv::cuda::PtrStepSz<short> nu = nonUnique ? at(maps[v][3]) : cv::cuda::PtrStepSz<short>();
        cv::cuda::PtrStepSz<int> rk(H, W, keys[v].data(), W * 4);
        const dim3 grid((W + 255) / 256, H);
#define RUN(NS, U) \
        launch(grid, 8, [&]() { NS::wtaKernel<U>(sum, W, p, windows, at(maps[v][0]), at(maps[v][1]), rk, nu); })
        if (v == 0) { if (unique) RUN(oldv, true); else RUN(oldv, false); }
        else { if (unique) RUN(newv, true); else RUN(newv, false); }
    }
    size_t diff = 0, invalid = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
    {
        for (int m = 0; m < 4; m++) diff += maps[0][m][i] != maps[1][m][i];
        diff += keys[0][i] != keys[1][i];
        invalid += maps[0][0][i] == NO_DISP;
    }
    printf("seed %d: %dx%d D %d minD %d windows %d unique %d subpixel %d nonUnique %d spread %d: %zu pixels, "
           "%zu not unique, %zu differ\n", seed, W, H, D, minD, windowed, unique, subpixel, nonUnique, spread,
           (size_t)W * H, invalid, diff);
    return diff != 0;
}
