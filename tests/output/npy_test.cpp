// SPDX-License-Identifier: MIT
// The .npy writer (src/output/npy.h) read back by NumPy itself (Debian's
// python3-numpy, a build dependency): shapes, dtypes, every element of
// arrays written in shuffled blocks from two threads, a 2e9-element array
// (sparse: only a few blocks written) opened memory-mapped, and no file under
// the final name unless finish() ran.
#include "src/output/npy.h"

#include "support/fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace plancheck {
namespace {

// Runs python3 with NumPy on `script` (argv[1] = file); its stdout.
std::string numpy_says(const testing::TempDir& dir, const std::string& script, const std::filesystem::path& file) {
  testing::write_text(dir / "read.py", "import sys, numpy as np\n" + script);
  const std::filesystem::path out = dir / "out.txt";
  const int status = testing::run_command("/usr/bin/python3 \"" + (dir / "read.py").string() + "\" \"" + file.string() +
                                          "\" > \"" + out.string() + "\" 2>&1");
  std::string text = testing::read_text(out);
  EXPECT_EQ(status, 0) << text;
  return text;
}

TEST(Npy, HeaderIsAlignedAndSaysShapeAndType) {
  for (const auto& shape : std::vector<std::vector<std::uint64_t>>{{}, {5}, {73, 32, 35, 47}, {0, 3}}) {
    for (NpyType t : {NpyType::kUint8, NpyType::kFloat32}) {
      const std::string h = npy_header(t, shape);
      EXPECT_EQ(h.size() % 64, 0u);
      EXPECT_EQ(h.substr(0, 6), "\x93NUMPY");
      EXPECT_EQ(static_cast<std::size_t>(static_cast<unsigned char>(h[8]) | static_cast<unsigned char>(h[9]) << 8), h.size() - 10);
      EXPECT_EQ(h.back(), '\n');
      EXPECT_NE(h.find(t == NpyType::kUint8 ? "'|u1'" : "'<f4'"), std::string::npos);
    }
  }
  EXPECT_NE(npy_header(NpyType::kUint8, {5}).find("'shape': (5,)"), std::string::npos);
  EXPECT_NE(npy_header(NpyType::kUint8, {73, 32, 35, 47}).find("'shape': (73, 32, 35, 47)"), std::string::npos);
}

TEST(Npy, NumPyReadsBlocksWrittenInAnyOrderFromTwoThreads) {
  testing::TempDir dir("npy");
  const std::vector<std::uint64_t> shape = {7, 11, 13};
  const std::size_t n = 7 * 11 * 13;
  std::vector<std::uint8_t> v(n);
  std::vector<float> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    v[i] = static_cast<std::uint8_t>((i * 37 + 5) % 251);
    f[i] = static_cast<float>(std::ldexp(static_cast<double>(i) - 400.0, -3));
  }
  f[3] = -0.0f;
  f[4] = std::numeric_limits<float>::denorm_min();
  f[5] = std::numeric_limits<float>::max();
  // Blocks of 17 in a shuffled order, split between two threads.
  std::vector<std::size_t> blocks((n + 16) / 17);
  std::iota(blocks.begin(), blocks.end(), 0);
  std::shuffle(blocks.begin(), blocks.end(), std::mt19937(7));
  {
    NpyWriter vw(dir / "verdict.npy", NpyType::kUint8, shape);
    NpyWriter fw(dir / "distance.npy", NpyType::kFloat32, shape);
    auto work = [&](std::size_t from, std::size_t to) {
      for (std::size_t k = from; k < to; ++k) {
        const std::size_t first = blocks[k] * 17, count = std::min<std::size_t>(17, n - first);
        vw.write(first, v.data() + first, count);
        fw.write(first, f.data() + first, count);
      }
    };
    std::thread t1(work, 0, blocks.size() / 2), t2(work, blocks.size() / 2, blocks.size());
    t1.join();
    t2.join();
    EXPECT_FALSE(std::filesystem::exists(dir / "verdict.npy"));  // not before finish()
    vw.finish();
    fw.finish();
  }
  // NumPy's own reading, element by element against what was written
  // (the same formulas in Python).
  EXPECT_EQ(numpy_says(dir,
                       "a = np.load(sys.argv[1])\n"
                       "e = np.array([(i * 37 + 5) % 251 for i in range(a.size)], dtype=np.uint8).reshape(7, 11, 13)\n"
                       "print(a.dtype, a.shape, bool((a == e).all()))\n",
                       dir / "verdict.npy"),
            "uint8 (7, 11, 13) True\n");
  EXPECT_EQ(numpy_says(dir,
                       "a = np.load(sys.argv[1])\n"
                       "e = np.ldexp(np.arange(a.size, dtype=np.float64) - 400.0, -3).astype(np.float32)\n"
                       "e[3] = -0.0; e[4] = np.finfo(np.float32).smallest_subnormal; e[5] = np.finfo(np.float32).max\n"
                       "e = e.reshape(7, 11, 13)\n"
                       "print(a.dtype, a.shape, bool((a.view(np.uint32) == e.view(np.uint32)).all()))\n",
                       dir / "distance.npy"),
            "float32 (7, 11, 13) True\n");
}

TEST(Npy, TwoBillionElementsWithBoundedMemory) {
  testing::TempDir dir("npy-big");
  const std::vector<std::uint64_t> shape = {50000, 40000};  // 2e9 uint8: a sparse file, few blocks written
  {
    NpyWriter w(dir / "big.npy", NpyType::kUint8, shape);
    const std::vector<std::uint8_t> head(1000, 1), tail(1000, 3);
    w.write(0, head.data(), head.size());
    w.write(w.elements() - tail.size(), tail.data(), tail.size());
    EXPECT_THROW(w.write(w.elements() - 10, tail.data(), 11), std::out_of_range);
    w.finish();
  }
  EXPECT_EQ(numpy_says(dir,
                       "a = np.load(sys.argv[1], mmap_mode='r')\n"
                       "print(a.dtype, a.shape, int(a[0, :1000].sum()), int(a[-1, -1000:].sum()), int(a[25000, 7]))\n",
                       dir / "big.npy"),
            "uint8 (50000, 40000) 1000 3000 0\n");
}

TEST(Npy, AWriterNotFinishedLeavesNoFile) {
  testing::TempDir dir("npy-cut");
  {
    NpyWriter w(dir / "verdict.npy", NpyType::kUint8, {10});
    const std::uint8_t x = 2;
    w.write(0, &x, 1);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "verdict.npy"));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  EXPECT_THROW(NpyWriter(dir / "no-such-folder" / "x.npy", NpyType::kUint8, {1}), std::runtime_error);
}

}  // namespace
}  // namespace plancheck
