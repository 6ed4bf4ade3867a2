// SPDX-License-Identifier: GPL-3.0-or-later
//
// jemalloc's settings for the programs that link it (the `shadow` command line, shadow-bench,
// the tests; CMakeLists.txt, LIBSHADOW_USE_JEMALLOC). jemalloc reads this symbol at start-up;
// MALLOC_CONF in the environment still overrides it (for instance MALLOC_CONF=thp:default).
//
// thp:always asks for transparent huge pages on jemalloc's memory (madvise, where the kernel's
// transparent_hugepage setting is "madvise", as on Debian). The engine revisits the scene's
// prepared faces, the light-space grids and a series' table every few hundred milliseconds; on
// the 2-core benchmark machine (a virtual machine) a 4 KiB page not touched for ~100 ms then
// costs 3-8 microseconds to read or write again, a 2 MiB page nothing measurable
// (docs/benchmarks.md, "Ninth look"). Measured there side by side: a sample of the year's suns
// on the 1,000-box city 20% less time (fast) and 13% (exact); a million faces the same wall
// time (the shadows 12% faster, reading 0.7 s slower: huge pages are zeroed whole) and 5% more
// peak memory; on a later host 1-2 s slower, on another 2 s faster, so `shadow compute` reads
// and writes on the page size it measures cheaper on its host (tools/shadow/page_policy.hpp).
extern "C" {
extern const char* malloc_conf;
const char* malloc_conf = "thp:always";
}
