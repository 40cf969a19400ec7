/*
 * Copyright 2026 gr-nrsar authors.
 *
 * SPDX-License-Identifier: GPL-3.0-or-later
 */

// Runs a libFuzzer target without libFuzzer: feeds every file of the directories (or the
// files) given on the command line to LLVMFuzzerTestOneInput once. Built with the normal
// compiler for ctest (fuzz_<name>_regress), so the seed corpus and every stored crash input
// (tests/fuzz/regressions/<target>/) stay regression tests of the ordinary build.
// A missing folder is skipped (regressions/<target>/ appears with the first crash), but a
// run that feeds no input at all fails: it would pass without testing anything.

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

int main(int argc, char** argv)
{
    if (LLVMFuzzerInitialize)
        LLVMFuzzerInitialize(&argc, &argv);
    namespace fs = std::filesystem;
    std::vector<fs::path> inputs;
    for (int i = 1; i < argc; ++i) {
        const fs::path p(argv[i]);
        if (fs::is_directory(p)) {
            for (const auto& entry : fs::directory_iterator(p))
                if (entry.is_regular_file() && entry.path().filename().string()[0] != '.' &&
                    entry.path().filename() != "README.md")
                    inputs.push_back(entry.path());
        } else if (fs::is_regular_file(p)) {
            inputs.push_back(p);
        } else if (!fs::exists(p)) {
            continue; // no regression inputs yet
        }
    }
    std::sort(inputs.begin(), inputs.end());
    for (const auto& path : inputs) {
        std::ifstream in(path, std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                      std::istreambuf_iterator<char>());
        std::printf("%s (%zu bytes)\n", path.c_str(), bytes.size());
        std::fflush(stdout);
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                               bytes.size());
    }
    std::printf("%zu inputs ran\n", inputs.size());
    if (inputs.empty()) {
        std::fprintf(stderr,
                     "no input: add seeds to tests/fuzz/corpus/<target>/ "
                     "(tests/fuzz/README.md)\n");
        return 1;
    }
    return 0;
}
