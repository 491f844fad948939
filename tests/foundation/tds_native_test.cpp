// SPDX-License-Identifier: MIT
// The strict native 3ds reader (src/scene/tds_native.h) against assimp: on
// every 3ds file it takes, load_model's answer without assimp equals its
// answer through assimp field by field, bit for bit (3ds test models, the
// fuzz corpus, random files from the dataset writer, byte-mutated files);
// and it declines what it does not handle, which then loads through assimp.
#include "src/scene/model_loader.h"
#include "src/scene/tds_native.h"
#include "src/scene/tds_reader.h"

#include "datasets/tds_writer.h"
#include "tests/foundation/fixtures.h"
#include "tests/support/same_model.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace plancheck {
namespace {

using testing::kAssimpModels;

std::vector<unsigned char> bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write(const std::filesystem::path& p, const std::vector<unsigned char>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

using testing::expect_same_model;
using testing::load_model_outcome;
using testing::same_bits;

// The strict reader's objects are what the lenient walk the loader matches
// against reads (name, points bit for bit, faces, materials).
void expect_objects_agree(const std::vector<unsigned char>& bytes, const TdsFile& strict, const std::string& label) {
  const std::vector<TdsObject> lenient = read_tds_objects(bytes);
  ASSERT_EQ(lenient.size(), strict.objects.size()) << label;
  for (std::size_t i = 0; i < lenient.size(); ++i) {
    const TdsObject &a = lenient[i], &b = strict.objects[i];
    EXPECT_TRUE(a.name == b.name && a.faces == b.faces && a.face_material == b.face_material) << label << " " << i;
    ASSERT_EQ(a.points.size(), b.points.size()) << label << " " << i;
    for (std::size_t p = 0; p < a.points.size(); ++p) ASSERT_TRUE(same_bits(a.points[p], b.points[p])) << label;
  }
}

// One file through both paths when the strict reader takes it; true if it did.
bool compare_file(const std::filesystem::path& file, const std::string& label) {
  const std::vector<unsigned char> bytes = bytes_of(file);
  const std::optional<TdsFile> strict = read_3ds_strict(bytes);
  if (!strict) return false;
  expect_objects_agree(bytes, *strict, label);
  expect_same_model(load_model_outcome(file, false), load_model_outcome(file, true), label);
  return true;
}

// A random node tree through the dataset's 3ds writer (keyframer, dummies,
// identity tracks): names, nesting, shared and unused points, degenerate
// and repeated faces, coordinates of every size.
std::vector<unsigned char> random_tds(std::mt19937& rng) {
  std::uniform_int_distribution<int> count(1, 7), points(3, 30), faces(1, 40);
  std::uniform_real_distribution<float> coord(-3.0f, 3.0f);
  std::vector<TdsNode> nodes(static_cast<std::size_t>(count(rng)));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    TdsNode& n = nodes[i];
    n.name = (rng() % 3 == 0 ? "Part_" : "n") + std::to_string(i);
    n.parent = i == 0 || rng() % 3 == 0 ? -1 : static_cast<int>(rng() % i);
    if (rng() % 5 == 0) continue;  // a group node
    const int np = points(rng);
    const float size = std::pow(10.0f, static_cast<float>(rng() % 7) - 3.0f);
    for (int p = 0; p < np; ++p) n.mesh.vertices.push_back({coord(rng) * size, coord(rng) * size, coord(rng) * size});
    if (rng() % 4 == 0) n.mesh.vertices.push_back({0.0f, -0.0f, 0.0f});
    for (int f = faces(rng); f > 0; --f) {
      std::array<std::uint32_t, 3> t{};
      for (auto& k : t) k = static_cast<std::uint32_t>(rng() % static_cast<unsigned>(n.mesh.vertices.size()));
      n.mesh.faces.push_back(t);
    }
  }
  return tds_serialize(nodes);
}

// The same bytes with a few of them changed: random bytes, a chunk length
// or count set to an edge value, a cut, a piece repeated.
std::vector<unsigned char> mutate(std::vector<unsigned char> b, std::mt19937& rng) {
  const int kind = static_cast<int>(rng() % 7);
  auto at = [&] { return static_cast<std::size_t>(rng() % b.size()); };
  if (kind == 0) {
    for (int k = 1 + static_cast<int>(rng() % 4); k > 0; --k) b[at()] = static_cast<unsigned char>(rng());
  } else if (kind == 1 && b.size() > 4) {
    const std::size_t i = at() % (b.size() - 3);
    static const std::uint32_t edges[] = {0, 1, 5, 6, 7, 0xFFFF, 0x10000, 0xFFFFFFFF, 0x7FFFFFFF};
    const std::uint32_t v = edges[rng() % std::size(edges)] + static_cast<std::uint32_t>(rng() % 3) - 1;
    for (int k = 0; k < 4; ++k) b[i + k] = static_cast<unsigned char>(v >> (8 * k));
  } else if (kind == 2) {
    b.resize(at());
  } else if (kind == 3) {
    const std::size_t i = at(), n = std::min<std::size_t>(b.size() - i, 1 + rng() % 64);
    std::vector<unsigned char> piece(b.begin() + static_cast<long>(i), b.begin() + static_cast<long>(i + n));
    b.insert(b.begin() + static_cast<long>(at()), piece.begin(), piece.end());
  } else if (kind == 6 && b.size() > 4) {
    // Any float (a point, a matrix entry, a key, a pivot) to a random value.
    const std::size_t i = at() % (b.size() - 3);
    const float f = std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng);
    std::uint32_t v;
    std::memcpy(&v, &f, 4);
    for (int k = 0; k < 4; ++k) b[i + k] = static_cast<unsigned char>(v >> (8 * k));
  } else if (kind == 5) {
    // A keyframer node's parent index (0xB010: name, two flag words, parent):
    // assimp's placement of nodes with 16-bit positions that wrap.
    std::vector<std::size_t> headers;
    for (std::size_t i = 0; i + 6 < b.size(); ++i)
      if (b[i] == 0x10 && b[i + 1] == 0xB0) headers.push_back(i);
    if (!headers.empty()) {
      std::size_t at = headers[rng() % headers.size()] + 6;
      while (at < b.size() && b[at] != 0) ++at;
      at += 5;
      static const unsigned parents[] = {0, 1, 2, 3, 0xFFFF, 0xFFFE, 0x7FFF, 0x8000, 0xFFD2};
      const unsigned v = rng() % 2 ? parents[rng() % std::size(parents)] : static_cast<unsigned>(rng() % 8);
      if (at + 1 < b.size()) {
        b[at] = static_cast<unsigned char>(v);
        b[at + 1] = static_cast<unsigned char>(v >> 8);
      }
    }
  } else {
    // A float of a point, a key or a matrix: to 0, -0, 1 or a non-finite.
    static const std::uint32_t floats[] = {0, 0x80000000u, 0x3F800000u, 0x7F800000u, 0x7FC00000u, 0xBF800000u};
    if (b.size() > 4) {
      const std::size_t i = at() % (b.size() - 3);
      const std::uint32_t v = floats[rng() % std::size(floats)];
      for (int k = 0; k < 4; ++k) b[i + k] = static_cast<unsigned char>(v >> (8 * k));
    }
  }
  if (b.empty()) b.push_back(0);
  return b;
}

TEST(Native3ds, EveryTestModelItTakesEqualsAssimp) {
  int taken = 0, files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kAssimpModels)) {
    std::string ext = entry.path().extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!entry.is_regular_file() || ext != ".3ds") continue;
    ++files;
    taken += compare_file(entry.path(), entry.path().filename().string());
  }
  std::cout << "3ds test models: " << files << ", taken natively: " << taken << "\n";
  EXPECT_GE(files, 10);
}

TEST(Native3ds, FuzzCorpusFilesItTakesEqualAssimp) {
  testing::TempDir dir;
  int taken = 0;
  const auto corpus = std::filesystem::path(PLANCHECK_SOURCE_DIR) / "tests/fuzz/corpus/model";
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    std::vector<unsigned char> b = bytes_of(entry.path());
    if (b.empty() || b[0] % 8 != 0) continue;  // fuzz_model's first byte: 0 picks .3ds
    b.erase(b.begin());
    const auto file = dir.path() / "model.3ds";
    write(file, b);
    taken += compare_file(file, entry.path().filename().string());
  }
  std::cout << "fuzz corpus 3ds files taken natively: " << taken << "\n";
  EXPECT_GE(taken, 1);  // native-tree-3ds: a dummy group, a position key
}

// load_model's `meanwhile` runs beside the native read as it runs beside
// assimp's child, and has stopped when load_model returns.
TEST(Native3ds, MeanwhileThreadRunsBesideTheNativeRead) {
  testing::TempDir dir;
  std::mt19937 rng(7);
  const auto file = dir.path() / "tree.3ds";
  std::vector<unsigned char> bytes;
  do bytes = random_tds(rng);
  while (read_tds_objects(bytes).empty());
  write(file, bytes);
  ASSERT_TRUE(read_3ds_strict(file));
  std::atomic<bool> ran{false}, stopped{false};
  std::vector<Mesh> drawn;
  Scene s;
  load_model(file, 0.25, s, {}, [&](const DrawnMeshes& meshes, const std::atomic<bool>& stop) {
    ran = true;
    drawn = meshes();  // from the objects the native reader read
    while (!stop) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    stopped = true;
  });
  EXPECT_TRUE(ran);
  EXPECT_TRUE(stopped);
  EXPECT_FALSE(s.parts.empty());
  // The same meshes as read from the file again.
  const std::vector<Mesh> expected = drawn_object_meshes(file, 0.25);
  ASSERT_EQ(drawn.size(), expected.size());
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    ASSERT_EQ(drawn[i].vertices.size(), expected[i].vertices.size());
    for (std::size_t v = 0; v < drawn[i].vertices.size(); ++v)
      ASSERT_TRUE(same_bits(drawn[i].vertices[v], expected[i].vertices[v]));
    EXPECT_EQ(drawn[i].triangles, expected[i].triangles);
  }
}

TEST(Native3ds, RandomWriterFilesAreTakenAndEqualAssimp) {
  testing::TempDir dir;
  std::mt19937 rng(16);
  for (int i = 0; i < 40; ++i) {
    const auto file = dir.path() / ("random" + std::to_string(i) + ".3ds");
    const std::vector<unsigned char> bytes = random_tds(rng);
    write(file, bytes);
    // In the subset, unless it has no faces at all (which assimp refuses).
    const bool faces = !read_tds_objects(bytes).empty();
    EXPECT_EQ(compare_file(file, file.filename().string()), faces) << file.filename();
  }
}

// Malformed and altered files: the reader never crashes or reads out of
// bounds (the sanitizer builds run this), and whenever it takes one, the
// answer is assimp's. Most mutants are declined; those taken are compared.
TEST(Native3ds, MutatedFilesItTakesEqualAssimp) {
  testing::TempDir dir;
  std::mt19937 rng(4);
  std::vector<std::vector<unsigned char>> seeds;
  for (int i = 0; i < 6; ++i) seeds.push_back(random_tds(rng));
  for (const char* name : {"3DS/fels.3ds", "3DS/test1.3ds", "3DS/CameraRollAnimWithChildObject.3ds"})
    seeds.push_back(bytes_of(kAssimpModels / name));
  int taken = 0, compared = 0, read = 0;
  for (int i = 0; i < 3000; ++i) {
    std::vector<unsigned char> b = seeds[static_cast<std::size_t>(i) % seeds.size()];
    for (int k = 1 + static_cast<int>(rng() % 3); k > 0; --k) b = mutate(std::move(b), rng);
    ++read;
    const std::optional<TdsFile> strict = read_3ds_strict(b);
    if (!strict) continue;
    ++taken;
    if (compared >= 250) continue;  // assimp's side costs a process each
    ++compared;
    const auto file = dir.path() / "mutant.3ds";
    write(file, b);
    const std::string label = "mutant " + std::to_string(i);
    expect_objects_agree(b, *strict, label);
    expect_same_model(load_model_outcome(file, false), load_model_outcome(file, true), label);
  }
  std::cout << read << " mutants read, " << taken << " taken, " << compared << " compared with assimp\n";
  EXPECT_GE(compared, 200);
}

// What the reader declines, each on a file it otherwise takes (most still
// load, through assimp); and the transforms it takes, each equal to assimp.
TEST(Native3ds, DeclinesWhatItDoesNotHandleAndTakesTransforms) {
  testing::TempDir dir;
  std::vector<TdsNode> nodes(2);
  nodes[0].name = "base";
  nodes[0].mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  nodes[0].mesh.faces = {{0, 1, 2}, {0, 1, 3}};
  nodes[1].name = "basf";
  nodes[1].parent = 0;
  nodes[1].mesh = nodes[0].mesh;
  const std::vector<unsigned char> good = tds_serialize(nodes);
  ASSERT_TRUE(read_3ds_strict(good));

  auto u16 = [](const std::vector<unsigned char>& b, std::size_t at) { return unsigned(b[at] | (b[at + 1] << 8)); };
  auto find = [&](const std::vector<unsigned char>& b, unsigned id, int nth = 0) {
    for (std::size_t i = 0; i + 1 < b.size(); ++i)
      if (u16(b, i) == id && nth-- == 0) return i;
    ADD_FAILURE() << "no chunk " << id;
    return std::size_t{0};
  };
  auto put_f32 = [](std::vector<unsigned char>& b, std::size_t at, float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    for (int k = 0; k < 4; ++k) b[at + k] = static_cast<unsigned char>(u >> (8 * k));
  };
  // Appends chunk `id` with `body` at the end of the chunk starting at `parent`
  // (and grows every chunk around it).
  auto insert = [&](std::vector<unsigned char> b, std::size_t parent, unsigned id, std::vector<unsigned char> body) {
    const std::uint32_t len = static_cast<std::uint32_t>(body.size() + 6);
    std::vector<unsigned char> c = {static_cast<unsigned char>(id), static_cast<unsigned char>(id >> 8)};
    for (int k = 0; k < 4; ++k) c.push_back(static_cast<unsigned char>(len >> (8 * k)));
    c.insert(c.end(), body.begin(), body.end());
    const std::size_t end = parent + (b[parent + 2] | (b[parent + 3] << 8) | (b[parent + 4] << 16));
    b.insert(b.begin() + static_cast<long>(end), c.begin(), c.end());
    // Grow the parent and its ancestors.
    std::function<void(std::size_t, std::size_t)> walk = [&](std::size_t from, std::size_t to) {
      for (std::size_t at = from; at + 6 <= to;) {
        const std::size_t l = b[at + 2] | (b[at + 3] << 8) | (b[at + 4] << 16) | (std::size_t(b[at + 5]) << 24);
        if (l < 6 || at + l > to) return;
        if (at <= parent && parent < at + l) {
          const std::size_t nl = l + c.size();
          for (int k = 0; k < 4; ++k) b[at + 2 + k] = static_cast<unsigned char>(nl >> (8 * k));
          const unsigned cid = u16(b, at);
          std::size_t body_at = at + 6;
          if (cid == 0x4000) {
            while (b[body_at] != 0) ++body_at;
            ++body_at;
          }
          if (at != parent) walk(body_at, at + nl);
          return;
        }
        at += l;
      }
    };
    walk(0, b.size());
    return b;
  };

  std::vector<std::pair<std::string, std::vector<unsigned char>>> cases;
  {
    auto b = good;
    cases.push_back({"material", insert(b, find(b, 0x3D3D), 0xAFFF, {0x00, 0xA0, 8, 0, 0, 0, 'm', 0})});
  }
  {
    auto b = good;
    cases.push_back({"texture coordinates", insert(b, find(b, 0x4100), 0x4140, {0, 0})});
  }
  {
    auto b = good;
    std::vector<unsigned char> camera = {'c', 0, 0x00, 0x47, 38, 0, 0, 0};
    camera.resize(camera.size() + 32, 0);  // position, target, roll, lens
    camera[8 + 16] = 0x80;                 // target y = 1: a proper look-at
    camera[8 + 17] = 0x3F;
    camera[8 + 14] = 0;
    cases.push_back({"camera", insert(b, find(b, 0x3D3D), 0x4000, camera)});
  }
  {
    auto b = good;
    b[find(b, 0xB020) + 6 + 10] = 2;  // two keys claimed (the bytes hold one)
    cases.push_back({"two keys", b});
  }
  {
    auto b = good;
    b[find(b, 0xB010, 1) + 6 + 3] = 'e';  // the second node is named "base" too: an instance
    cases.push_back({"instance", b});
  }
  {
    auto b = good;
    b[find(b, 0x4120) + 6 + 2] = 9;  // a face naming point 9 of 4
    cases.push_back({"face out of range", b});
  }
  {
    auto b = good;
    b.push_back(0);
    cases.push_back({"trailing byte", b});
  }
  // Transforms are taken: assimp's float math on them is redone natively.
  std::vector<std::pair<std::string, std::vector<unsigned char>>> taken;
  for (float v : {0.5f, -1.0f, 2.0f, 1e-3f, 0.0f}) {
    const std::string at = " " + std::to_string(v);
    {
      auto b = good;
      put_f32(b, find(b, 0xB021) + 6 + 20, v * 3.0f);  // the rotation key's angle
      put_f32(b, find(b, 0xB021) + 6 + 24, v);         // and its axis x
      taken.push_back({"rotation" + at, b});
    }
    {
      auto b = good;
      put_f32(b, find(b, 0xB013, 1) + 6, v);
      put_f32(b, find(b, 0xB013, 1) + 14, -v);
      taken.push_back({"pivot" + at, b});
    }
    {
      auto b = good;
      put_f32(b, find(b, 0xB022) + 6 + 20, v);
      put_f32(b, find(b, 0xB020, 1) + 6 + 24, v);  // and the second node's position y
      taken.push_back({"scale" + at, b});
    }
    {
      auto b = good;
      put_f32(b, find(b, 0x4160) + 6 + 4, v);
      put_f32(b, find(b, 0x4160, 1) + 6 + 0, v);  // the second object's axes: mirrored at -1, singular at 0
      put_f32(b, find(b, 0x4160, 1) + 6 + 40, v * 7.0f);
      taken.push_back({"local axes" + at, b});
    }
    {
      auto b = good;
      std::vector<unsigned char> scale(4);
      std::memcpy(scale.data(), &v, 4);
      taken.push_back({"master scale" + at, insert(b, find(b, 0x3D3D), 0x0100, scale)});
    }
  }
  for (const auto& [what, b] : taken) {
    ASSERT_TRUE(read_3ds_strict(b)) << what;
    const auto file = dir.path() / "taken.3ds";
    write(file, b);
    expect_same_model(load_model_outcome(file, false), load_model_outcome(file, true), what);
  }

  for (const auto& [what, b] : cases) {
    EXPECT_FALSE(read_3ds_strict(b)) << what;
    const auto file = dir.path() / "declined.3ds";
    write(file, b);
    const testing::ModelOutcome o = load_model_outcome(file, true);
    const bool loads = what == "material" || what == "texture coordinates";
    if (loads) {
      EXPECT_EQ(o.error, "") << what;
    }
  }
}

}  // namespace
}  // namespace plancheck
