// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of crossparam/io.h and crossparam/validation.h: our own soup readers, mesh validation, feature files,
// the input checks of the entry points and atomic writing. Bad inputs are generated into a temporary directory
// at test time.
#include <crossparam/validation.h> // first: it must stand on its own, without the I/O headers
#include <crossparam/io.h>
#include <crossparam/parameters.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <random>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <unordered_map>
#include <vector>

// GCC flags free() in the replaced operator delete below as mismatched once it inlines both operators.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

// ------------------------------------------------------------------------------------------------
// Allocation tracking: the largest single allocation while tracking is on (to prove that absurd header
// counts are rejected before anything is reserved).
namespace {
std::atomic<bool> g_track_allocations{false};
std::atomic<std::size_t> g_largest_allocation{0};
} // namespace

void* operator new(std::size_t n) {
  if (g_track_allocations.load(std::memory_order_relaxed)) {
    std::size_t m = g_largest_allocation.load(std::memory_order_relaxed);
    while (n > m && !g_largest_allocation.compare_exchange_weak(m, n)) {
    }
  }
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return ::operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace {

namespace fs = std::filesystem;
using crossparam::Feature_correspondence;
using crossparam::Multi_feature_correspondence;
using crossparam::Feature_error;
using crossparam::Input_error;
using crossparam::Polygon_soup;
using Soup = crossparam::Polygon_soup;
using Mesh = crossparam::Surface_mesh;
using Polyhedron = CGAL::Polyhedron_3<crossparam::Kernel, CGAL::Polyhedron_items_with_id_3>;
using Plain_polyhedron = CGAL::Polyhedron_3<crossparam::Kernel>;

struct Allocation_watch {
  Allocation_watch() {
    g_largest_allocation = 0;
    g_track_allocations = true;
  }
  ~Allocation_watch() { g_track_allocations = false; }
  std::size_t largest() const { return g_largest_allocation.load(); }
};

// ------------------------------------------------------------------------------------------------ temp files

const fs::path& temp_dir() {
  struct Dir {
    fs::path path;
    Dir() {
      std::random_device rd;
      path = fs::temp_directory_path() /
             ("crossparam_test_io_" + std::to_string(::getpid()) + "_" + std::to_string(rd() % 1000000));
      fs::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static Dir dir;
  return dir.path;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const fs::path p = temp_dir() / name;
  std::ofstream os(p, std::ios::binary | std::ios::trunc);
  os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  os.close();
  EXPECT_TRUE(os.good()) << p;
  return p.string();
}

std::string read_file(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  std::ostringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

bool shared_dir_present() { return fs::is_directory(fs::path(CROSSPARAM_SHARED_DIR) / "data"); }

// ------------------------------------------------------------------------------------------------ errors

/// Runs f, which must throw E (or a subclass) whose message contains every keyword. Returns the message.
template <class E = Input_error, class F>
std::string expect_error(F&& f, std::vector<std::string> keywords) {
  try {
    f();
  } catch (const E& e) {
    const std::string msg = e.what();
    EXPECT_FALSE(msg.empty());
    for (const std::string& k : keywords)
      EXPECT_NE(msg.find(k), std::string::npos) << "message \"" << msg << "\" lacks \"" << k << "\"";
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type, message: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no exception thrown; expected one mentioning " << (keywords.empty() ? "" : keywords[0]);
  return "";
}

std::string expect_soup_error(const std::string& path, std::vector<std::string> keywords) {
  keywords.push_back(path + ": ");
  return expect_error([&] { crossparam::read_polygon_soup(path); }, keywords);
}

std::string expect_mesh_error(const std::string& path, std::vector<std::string> keywords) {
  keywords.push_back(path + ": ");
  return expect_error([&] {
    Mesh m;
    crossparam::read_triangle_mesh(path, m);
  }, keywords);
}

std::string expect_soup_mesh_error(const Soup& soup, std::vector<std::string> keywords) {
  keywords.push_back("mysoup: ");
  return expect_error([&] {
    Mesh m;
    crossparam::soup_to_triangle_mesh(soup, m, "mysoup");
  }, keywords);
}

// ------------------------------------------------------------------------------------------------ shapes

Soup octahedron() {
  Soup s;
  s.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  s.polygons = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return s;
}

Soup tetrahedron(double dx = 0) {
  Soup s;
  s.points = {{dx, 0, 0}, {dx + 1, 0, 0}, {dx, 1, 0}, {dx, 0, 1}};
  s.polygons = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return s;
}

/// A torus as an n x m grid with wrap-around (genus 1).
Soup torus(int n = 6, int m = 5) {
  Soup s;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * pi * i / n, v = 2 * pi * j / m;
      s.points.push_back({(2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  auto id = [&](int i, int j) { return static_cast<std::size_t>(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      s.polygons.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.polygons.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

/// Appends the polygons of b (shifted) to a.
Soup join(const Soup& a, const Soup& b, std::size_t shared_prefix = 0) {
  // Vertices 0..shared_prefix-1 of b are identified with vertices 0..shared_prefix-1 of a.
  Soup s = a;
  const std::size_t base = a.points.size();
  auto map = [&](std::size_t v) { return v < shared_prefix ? v : base + v - shared_prefix; };
  for (std::size_t i = shared_prefix; i < b.points.size(); ++i) s.points.push_back(b.points[i]);
  for (const auto& p : b.polygons) {
    std::vector<std::size_t> q;
    for (std::size_t v : p) q.push_back(map(v));
    s.polygons.push_back(q);
  }
  return s;
}

std::string num(double v) {
  std::ostringstream ss;
  ss.precision(17);
  ss << v;
  return ss.str();
}

std::string off_text(const Soup& s) {
  std::string t = "OFF\n" + std::to_string(s.points.size()) + " " + std::to_string(s.polygons.size()) + " 0\n";
  for (const auto& p : s.points) t += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + "\n";
  for (const auto& f : s.polygons) {
    t += std::to_string(f.size());
    for (std::size_t v : f) t += " " + std::to_string(v);
    t += "\n";
  }
  return t;
}

std::string obj_text(const Soup& s) {
  std::string t = "# test\n";
  for (const auto& p : s.points) t += "v " + num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + "\n";
  for (const auto& f : s.polygons) {
    t += "f";
    for (std::size_t v : f) t += " " + std::to_string(v + 1);
    t += "\n";
  }
  return t;
}

std::string ply_ascii_text(const Soup& s) {
  std::string t = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(s.points.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  std::to_string(s.polygons.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : s.points) t += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + "\n";
  for (const auto& f : s.polygons) {
    t += std::to_string(f.size());
    for (std::size_t v : f) t += " " + std::to_string(v);
    t += "\n";
  }
  return t;
}

bool host_big_endian() { return crossparam::internal::soup_io::host_is_big_endian(); }

struct Bytes {
  std::string s;
  bool big = false;
  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big != host_big_endian()) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
};

/// Binary PLY: double x, float y, int16-free (z float), an extra uchar, a face list uchar/int and an extra
/// element with a list property. Coordinates written as given (also NaN).
std::string ply_binary(const Soup& s, bool big) {
  std::string h = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\ncomment made by test_io\nelement vertex " + std::to_string(s.points.size()) +
                  "\nproperty double x\nproperty float y\nproperty uchar quality\nproperty double z\n"
                  "element face " + std::to_string(s.polygons.size()) +
                  "\nproperty uchar flags\nproperty list uchar uint vertex_indices\nproperty list ushort float texcoord\n"
                  "element material 2\nproperty list int uchar name\nproperty short id\nend_header\n";
  Bytes b;
  b.big = big;
  for (const auto& p : s.points) {
    b.put<double>(p[0]).put<float>(static_cast<float>(p[1])).put<std::uint8_t>(7).put<double>(p[2]);
  }
  for (const auto& f : s.polygons) {
    b.put<std::uint8_t>(1).put<std::uint8_t>(static_cast<std::uint8_t>(f.size()));
    for (std::size_t v : f) b.put<std::uint32_t>(static_cast<std::uint32_t>(v));
    b.put<std::uint16_t>(2).put<float>(0.5f).put<float>(0.25f);
  }
  for (int m = 0; m < 2; ++m) b.put<std::int32_t>(3).put<std::uint8_t>('a').put<std::uint8_t>('b').put<std::uint8_t>('c').put<std::int16_t>(static_cast<std::int16_t>(m));
  return h + b.s;
}

std::string stl_ascii_text(const Soup& s) {
  std::string t = "solid test\n";
  for (const auto& f : s.polygons) {
    t += "  facet normal 0 0 0\n    outer loop\n";
    for (std::size_t v : f)
      t += "      vertex " + num(s.points[v][0]) + " " + num(s.points[v][1]) + " " + num(s.points[v][2]) + "\n";
    t += "    endloop\n  endfacet\n";
  }
  return t + "endsolid test\n";
}

std::string stl_binary(const Soup& s) {
  Bytes b;
  b.s.assign(80, ' ');
  b.put<std::uint32_t>(static_cast<std::uint32_t>(s.polygons.size()));
  for (const auto& f : s.polygons) {
    b.put<float>(0).put<float>(0).put<float>(0);
    for (std::size_t v : f)
      for (int k = 0; k < 3; ++k) b.put<float>(static_cast<float>(s.points[v][k]));
    b.put<std::uint16_t>(0);
  }
  // Binary STL is little-endian regardless of the host.
  if (host_big_endian()) {
    // Not expected on the test machines; the builder above used host order.
    ADD_FAILURE() << "big-endian host: binary STL test data not supported";
  }
  return b.s;
}

template <class TM>
std::vector<std::array<double, 3>> mesh_points(const TM& tm) {
  std::vector<std::array<double, 3>> out;
  for (auto v : vertices(tm)) {
    const auto& p = get(CGAL::vertex_point, tm, v);
    out.push_back({p.x(), p.y(), p.z()});
  }
  return out;
}

/// Faces of tm as vertex-position index triples (index = position in vertices(tm) order).
template <class TM>
std::vector<std::vector<std::size_t>> mesh_faces(const TM& tm) {
  std::unordered_map<typename boost::graph_traits<TM>::vertex_descriptor, std::size_t> index;
  for (auto v : vertices(tm)) index.emplace(v, index.size());
  std::vector<std::vector<std::size_t>> out;
  for (auto f : faces(tm)) {
    out.emplace_back();
    for (auto v : CGAL::vertices_around_face(halfedge(f, tm), tm)) out.back().push_back(index.at(v));
  }
  return out;
}

/// True if triangle a equals b up to a cyclic rotation (same orientation).
bool same_oriented(const std::vector<std::size_t>& a, const std::vector<std::size_t>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t r = 0; r < a.size(); ++r) {
    bool eq = true;
    for (std::size_t i = 0; i < a.size(); ++i) eq = eq && a[(i + r) % a.size()] == b[i];
    if (eq) return true;
  }
  return false;
}

void expect_mesh_equals_soup(const Mesh& m, const Soup& s) {
  ASSERT_EQ(num_vertices(m), s.points.size());
  ASSERT_EQ(num_faces(m), s.polygons.size());
  const auto pts = mesh_points(m);
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(pts[i], s.points[i]) << "vertex " << i;
  const auto fs = mesh_faces(m);
  for (std::size_t f = 0; f < fs.size(); ++f) EXPECT_TRUE(same_oriented(fs[f], s.polygons[f])) << "face " << f;
  // For Surface_mesh the vertex index is the position.
  std::size_t i = 0;
  for (auto v : vertices(m)) EXPECT_EQ(static_cast<std::size_t>(v), i++);
}

} // namespace

// ================================================================================================ reading

TEST(ReadSoup, OffOctahedronLoadsInFileOrder) {
  const Soup oct = octahedron();
  const std::string path = write_file("oct.off", off_text(oct));
  const Soup s = crossparam::read_polygon_soup(path);
  EXPECT_EQ(s.points, oct.points);
  EXPECT_EQ(s.polygons, oct.polygons);
  Mesh m;
  const auto report = crossparam::read_triangle_mesh(path, m);
  EXPECT_EQ(report.genus, 0);
  EXPECT_EQ(report.reoriented_faces, 0u);
  EXPECT_TRUE(report.warnings.empty());
  expect_mesh_equals_soup(m, oct);
}

TEST(ReadSoup, OffVariantsCommentsAndLineEndings) {
  const Soup oct = octahedron();
  // Counts on the header line, comments everywhere, colours on vertices and faces (COFF), CRLF.
  std::string t = "# leading comment\nCOFF 6 8 12 # counts on the first line\n";
  for (const auto& p : oct.points) t += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + " 255 0 0 255\r\n";
  t += "\n# faces\n";
  for (const auto& f : oct.polygons) t += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + " 0.1 0.2 0.3\r\n";
  EXPECT_EQ(crossparam::read_polygon_soup(write_file("c.off", t)).polygons, oct.polygons);

  // NOFF with normals, counts on the next line, UTF-8 BOM, no final newline, uppercase extension.
  t = "\xEF\xBB\xBFNOFF\n6 8 0\n";
  for (const auto& p : oct.points) t += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + " 0 0 1\n";
  for (const auto& f : oct.polygons) t += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  t.pop_back();
  const Soup s = crossparam::read_polygon_soup(write_file("n.OFF", t));
  EXPECT_EQ(s.points, oct.points);
  EXPECT_EQ(s.polygons, oct.polygons);

  // CNOFF and STOFF are accepted too; old-Mac CR line endings.
  for (const std::string kw : {"CNOFF", "STOFF"}) {
    std::string u = off_text(oct);
    u.replace(0, 3, kw);
    std::replace(u.begin(), u.end(), '\n', '\r');
    EXPECT_EQ(crossparam::read_polygon_soup(write_file("v.off", u)).polygons, oct.polygons) << kw;
  }
}

TEST(ReadSoup, ObjAllFaceFormsAndIgnoredStatements) {
  const std::string t =
      "mtllib x.mtl\no octa\ng group\ns 1\nusemtl red\n"
      "v 1 0 0\nv -1 0 0 1.0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1 1 0.5 0.5 0.5\n"
      "vt 0 0\nvt 1 0\nvn 0 0 1\nvp 0.5\nl 1 2\n"
      "f 1 3 5\n"              // a
      "f 3/1 2/2 5/1\n"        // a/b
      "f 2//1 4//1 5//1\n"     // a//c
      "f 4/1/1 1/2/1 5/1/1\n"  // a/b/c
      "f -4 -6 -1\n"           // relative: 3 1 6
      "f 2 3 6 # comment\n"
      "f 4 2 \\\n 6\n"         // continuation line
      "f 1 4 6\n";
  const Soup s = crossparam::read_polygon_soup(write_file("o.obj", t));
  EXPECT_EQ(s.points, octahedron().points);
  EXPECT_EQ(s.polygons, octahedron().polygons);
  Mesh m;
  EXPECT_EQ(crossparam::read_triangle_mesh(write_file("o.OBJ", t), m).genus, 0);
}

TEST(ReadSoup, PlyAsciiWithExtraPropertiesAndElements) {
  const Soup oct = octahedron();
  std::string t =
      "ply\r\nformat ascii 1.0\r\ncomment hello\r\nobj_info x\r\nelement vertex 6\r\nproperty float32 x\r\n"
      "property uchar red\r\nproperty double y\r\nproperty list uchar float junk\r\nproperty int z\r\n"
      "element face 8\r\nproperty list uint8 uint16 vertex_index\r\nproperty float q\r\n"
      "element edge 1\r\nproperty list int int vertex_indices\r\nend_header\r\n";
  for (const auto& p : oct.points)
    t += num(p[0]) + " 200 " + num(p[1]) + " 2 0.5 1.5 " + std::to_string(static_cast<int>(p[2])) + "\r\n";
  for (const auto& f : oct.polygons)
    t += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + " 0.5\r\n";
  t += "2 0 1\r\n";
  const Soup s = crossparam::read_polygon_soup(write_file("a.ply", t));
  EXPECT_EQ(s.points, oct.points);
  EXPECT_EQ(s.polygons, oct.polygons);
}

TEST(ReadSoup, PlyBinaryLittleAndBigEndian) {
  Soup oct = octahedron();
  oct.points[0] = {0.1, 0.5, 0.3};  // y goes through float: 0.5 is exact
  for (bool big : {false, true}) {
    const std::string path = write_file(big ? "be.ply" : "le.ply", ply_binary(oct, big));
    const Soup s = crossparam::read_polygon_soup(path);
    EXPECT_EQ(s.points, oct.points) << path;
    EXPECT_EQ(s.polygons, oct.polygons) << path;
  }
}

TEST(ReadSoup, StlAsciiAndBinaryMergeIdenticalVerticesInFirstSeenOrder) {
  const Soup oct = octahedron();
  for (const std::string& path : {write_file("a.stl", stl_ascii_text(oct)), write_file("b.STL", stl_binary(oct))}) {
    const Soup s = crossparam::read_polygon_soup(path);
    ASSERT_EQ(s.points.size(), 6u) << path;
    // First-seen order: 0, 2, 4, 1, 3, 5 of the octahedron.
    const std::vector<std::size_t> order = {0, 2, 4, 1, 3, 5};
    for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(s.points[i], oct.points[order[i]]) << path;
    EXPECT_EQ(s.polygons.size(), 8u);
    Mesh m;
    const auto r = crossparam::soup_to_triangle_mesh(s, m, path);
    EXPECT_EQ(r.genus, 0);
    EXPECT_EQ(r.reoriented_faces, 0u);
  }
  // An ascii STL whose size happens to look binary-compatible is still read as ascii when it is text.
  std::string t = stl_ascii_text(oct);
  const std::size_t n = 8;
  while ((t.size() - 84) % 50 != 0) t.insert(t.size() - 1, " ");
  std::uint32_t count = static_cast<std::uint32_t>((t.size() - 84) / 50);
  (void)count;
  (void)n;
  EXPECT_EQ(crossparam::read_polygon_soup(write_file("c.stl", t)).polygons.size(), 8u);
}

TEST(ReadSoup, MissingEmptyDirectoryAndUnknownFormat) {
  expect_soup_error((temp_dir() / "does_not_exist.off").string(), {"does not exist"});
  expect_soup_error(write_file("empty.off", ""), {"empty"});
  expect_soup_error(write_file("blank.obj", "\n\n# nothing\n"), {"no vertices"});
  expect_soup_error(write_file("points.obj", "v 0 0 0\nv 1 0 0\n"), {"no faces"});
  fs::create_directories(temp_dir() / "dir.off");
  expect_soup_error((temp_dir() / "dir.off").string(), {"directory"});
  expect_soup_error(write_file("mesh.xyz", off_text(octahedron())), {"unknown mesh file format", ".xyz"});
  expect_soup_error(write_file("mesh", off_text(octahedron())), {"unknown mesh file format", "no file extension"});
  expect_soup_error(write_file("garbage.off", "hello world\n"), {"line 1", "not an OFF file"});
  expect_soup_error(write_file("garbage.stl", std::string(100, 'x')), {"not a valid STL"});
  expect_soup_error(write_file("solidbin.stl", "solid" + std::string(100, '\x01')), {"not a valid STL", "binary data"});
  const std::string fifo = (temp_dir() / "fifo.off").string();  // would block forever if opened
  if (::mkfifo(fifo.c_str(), 0600) == 0) expect_soup_error(fifo, {"not a regular file"});
  expect_soup_error(write_file("garbage.ply", "plyx\n"), {"line 1", "not a PLY file"});
}

// ================================================================================================ file errors

TEST(FileErrors, TruncatedFiles) {
  const Soup oct = octahedron();
  std::string off = off_text(oct);
  // Cut in the middle of the vertices and of the faces: header counts are plausible for the bytes left only
  // when we pad the file, so pad with comment lines.
  {
    const std::string t = "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n" + std::string(200, '#') + "\n";
    expect_soup_error(write_file("trunc_v.off", t), {"file ends after 3 of 6 vertices", "truncated"});
  }
  {
    const std::size_t cut = off.find("3 1 2 5");
    const std::string t = off.substr(0, cut) + std::string(100, '#');
    expect_soup_error(write_file("trunc_f.off", t), {"file ends after 5 of 8 faces", "truncated"});
  }
  {
    expect_soup_error(write_file("trunc_cut.off", off.substr(0, off.size() - 40)), {"truncated"});
    expect_soup_error(write_file("trunc_header.off", "OFF\n100 200 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                      {"line 2", "declares 100 vertices and 200 faces", "bytes"});
  }
  // Binary PLY cut inside the face data.
  {
    const std::string ply = ply_binary(oct, false);
    expect_soup_error(write_file("trunc.ply", ply.substr(0, ply.size() - 60)), {"truncated"});
  }
  // ASCII PLY with one face line missing (padded so that the byte bound passes).
  {
    std::string t = ply_ascii_text(oct);
    t = t.substr(0, t.rfind("3 0 3 5")) + std::string(40, ' ');
    expect_soup_error(write_file("trunc_a.ply", t), {"file ends inside entry 7 of 8", "'face'", "truncated"});
  }
  // STL: ascii cut inside a facet, binary cut.
  {
    const std::string t = stl_ascii_text(oct);
    expect_soup_error(write_file("trunc.stl", t.substr(0, t.find("endloop", t.size() / 2))), {"truncated"});
    const std::string b = stl_binary(oct);
    expect_soup_error(write_file("trunc_b.stl", b.substr(0, b.size() - 20)), {"not a valid STL", "truncated"});
    const std::string e = t.substr(0, t.rfind("endsolid"));
    expect_soup_error(write_file("noend.stl", e), {"truncated"});
  }
  // OBJ: a face referring to a vertex that never comes.
  expect_soup_error(write_file("trunc.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"),
                    {"line 5", "face 1 refers to vertex 4", "out of range"});
}

TEST(FileErrors, UnparsableNumbers) {
  expect_soup_error(write_file("num1.off", "OFF\n3 1 0\n0 0 0\n1 0x 0\n0 1 0\n3 0 1 2\n"),
                    {"line 4", "vertex 1", "cannot parse coordinate", "'0x'"});
  expect_soup_error(write_file("num2.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n"),
                    {"line 6", "face 0", "cannot parse vertex index"});
  expect_soup_error(write_file("num3.off", "OFF\nthree 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                    {"line 2", "cannot parse the vertex count"});
  expect_soup_error(write_file("num4.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n"),
                    {"line 5", "expected 3 coordinates"});
  expect_soup_error(write_file("num.obj", "v 0 0 0\nv 1 0 0\nv 0 1 abc\nf 1 2 3\n"), {"line 3", "'abc'"});
  expect_soup_error(write_file("num2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n"), {"line 4", "cannot parse vertex index"});
  expect_soup_error(write_file("num3.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"), {"line 4", "index 0 is invalid"});
  std::string ply = ply_ascii_text(tetrahedron());
  ply.replace(ply.find("end_header\n") + 11, 1, "q");
  expect_soup_error(write_file("num.ply", ply), {"line 10", "cannot parse value", "'q"});
  expect_soup_error(write_file("num.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 zz\nendloop\nendfacet\nendsolid\n"),
                    {"line 6", "'zz'"});
}

TEST(FileErrors, FaceIndexOutOfRange) {
  Soup bad = octahedron();
  bad.polygons[3] = {3, 0, 12};
  // "OFF" is line 1, counts line 2, vertices lines 3-8, face 3 on line 12.
  expect_soup_error(write_file("range.off", off_text(bad)),
                    {"line 12: face 3 refers to vertex 12 but the file has 6 vertices", "out of range"});
  expect_soup_error(write_file("range.obj", obj_text(bad)), {"line 11", "face 3 refers to vertex 13", "out of range"});
  expect_soup_error(write_file("range_neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
                    {"line 4", "relative vertex index -4", "out of range"});
  expect_soup_error(write_file("range.ply", ply_ascii_text(bad)), {"line 19", "face 3 refers to vertex 12", "out of range"});
  expect_soup_error(write_file("range_b.ply", ply_binary(bad, false)), {"face 3 refers to vertex 12", "out of range"});
  expect_soup_error(write_file("range_bb.ply", ply_binary(bad, true)), {"face 3 refers to vertex 12", "out of range"});
  expect_soup_error(write_file("neg.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"), {"line 6", "vertex -1", "out of range"});
}

TEST(FileErrors, FacesWithFewerThanThreeVertices) {
  expect_soup_error(write_file("two.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), {"line 6", "face 0 has 2 vertices"});
  expect_soup_error(write_file("declared.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n"), {"line 6", "declares 4 vertices"});
  expect_soup_error(write_file("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"), {"line 4", "face 0 has 2 vertices"});
  std::string ply = ply_ascii_text(tetrahedron());
  ply.replace(ply.find("3 1 2 3"), 7, "2 1 2  ");
  expect_soup_error(write_file("two.ply", ply), {"face 3 has 2 vertices"});
  expect_soup_error(write_file("two.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n"),
                    {"line 2", "facet 0 has 2 vertices"});
}

TEST(FileErrors, NonFiniteCoordinates) {
  const std::string tail = "3\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_soup_error(write_file("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"), {"line 4", "vertex 1", "non-finite"});
  expect_soup_error(write_file("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n"), {"line 3", "vertex 2", "non-finite", "-inf"});
  {
    Soup s = tetrahedron();
    s.points[2][1] = std::numeric_limits<double>::quiet_NaN();
    expect_soup_error(write_file("nan_a.ply", ply_ascii_text(s)), {"line 12", "vertex 2", "non-finite"});
    expect_soup_error(write_file("nan_le.ply", ply_binary(s, false)), {"vertex 2", "non-finite"});
    expect_soup_error(write_file("nan_be.ply", ply_binary(s, true)), {"vertex 2", "non-finite"});
    s.points[2][1] = 0;
    s.points[3][2] = std::numeric_limits<double>::infinity();
    expect_soup_error(write_file("inf_le.ply", ply_binary(s, false)), {"vertex 3", "non-finite", "inf"});
    expect_soup_error(write_file("inf.stl", stl_binary(s)), {"triangle 1", "non-finite", "inf"});
    s.points[3][2] = -std::numeric_limits<double>::quiet_NaN();
    expect_soup_error(write_file("nan.stl", stl_binary(s)), {"triangle 1", "non-finite"});
    expect_soup_error(write_file("nan_a.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n"),
                      {"line 5", "non-finite"});
  }
  (void)tail;
}

TEST(FileErrors, ExtremeCoordinatesRejectedTinyAccepted) {
  expect_soup_error(write_file("big.off", "OFF\n3 1 0\n0 0 0\n1e150 0 0\n0 1 0\n3 0 1 2\n"),
                    {"line 4", "coordinate out of supported range"});
  expect_soup_error(write_file("big.obj", "v 0 0 0\nv 1 0 0\nv 0 -1e150 0\nf 1 2 3\n"), {"line 3", "coordinate out of supported range"});
  expect_soup_error(write_file("huge.off", "OFF\n3 1 0\n0 0 0\n1e400 0 0\n0 1 0\n3 0 1 2\n"),
                    {"line 4", "coordinate out of supported range"});
  {
    Soup s = tetrahedron();
    s.points[1][0] = 1e150;
    expect_soup_error(write_file("big.ply", ply_binary(s, false)), {"vertex 1", "coordinate out of supported range"});
  }
  // Tiny values (and underflow to zero) are fine.
  const Soup s = crossparam::read_polygon_soup(
      write_file("tiny.off", "OFF\n4 4 0\n0 0 0\n1e-150 0 0\n0 1e-400 1e-300\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
  EXPECT_EQ(s.points[1][0], 1e-150);
  EXPECT_EQ(s.points[2][1], 0.0);
  Mesh m;
  EXPECT_NO_THROW(crossparam::soup_to_triangle_mesh(s, m, "tiny"));
}

TEST(FileErrors, AbsurdHeaderCountsFailFastWithoutHugeAllocation) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::pair<std::string, std::string>> cases = {
      {"absurd1.off", "OFF\n4000000000 8000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"absurd2.off", "OFF 1000000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"absurd3.off", "OFF\n3 18446744073709551615 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"absurd4.off", "OFF\n3 18446744073709551616 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"absurd1.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" + std::string(64, '\0')},
      {"absurd2.ply", "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 3000000000\nproperty list uint int vertex_indices\nend_header\n" + std::string(64, '\0')},
      {"absurd3.ply", "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 0\n"},
      {"absurd4.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement junk 100000000000\nproperty double w\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n" + std::string(64, '\0')},
  };
  for (const auto& c : cases) {
    const std::string path = write_file(c.first, c.second);
    Allocation_watch watch;
    const std::string msg = expect_soup_error(path, {"line"});
    EXPECT_LT(watch.largest(), std::size_t(1) << 20) << c.first << ": " << msg;
  }
  // A list length in the data that cannot fit in the rest of the file.
  {
    Bytes b;
    for (int i = 0; i < 9; ++i) b.put<float>(0);
    b.put<std::uint32_t>(4000000000u).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
    const std::string path = write_file("absurd_list.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uint int vertex_indices\nend_header\n" + b.s);
    Allocation_watch watch;
    expect_soup_error(path, {"truncated"});
    EXPECT_LT(watch.largest(), std::size_t(1) << 20);
  }
  // A huge binary STL triangle count in a small file.
  {
    Bytes b;
    b.s.assign(80, ' ');
    b.put<std::uint32_t>(0xffffffffu);
    b.s += std::string(100, '\0');
    Allocation_watch watch;
    expect_soup_error(write_file("absurd.stl", b.s), {"not a valid STL", "4294967295 triangles"});
    EXPECT_LT(watch.largest(), std::size_t(1) << 20);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0);
}

TEST(FileErrors, PlyHeaderProblems) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_soup_error(write_file("pbe.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 3\nend_header\n" + body),
                    {"line 3", "'property' before any 'element'"});
  expect_soup_error(write_file("type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty flaot x\nend_header\n" + body),
                    {"line 4", "unknown PLY type", "'flaot'"});
  expect_soup_error(write_file("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"), {"end_header"});
  expect_soup_error(write_file("nofmt.ply", "ply\nelement vertex 3\nproperty float x\nend_header\n"), {"line 2", "before the 'format'"});
  expect_soup_error(write_file("fmt.ply", "ply\nformat binary 1.0\nend_header\n"), {"line 2", "unsupported PLY format"});
  expect_soup_error(write_file("ver.ply", "ply\nformat ascii 2.0\nend_header\n"), {"line 2", "unsupported PLY version"});
  expect_soup_error(write_file("kw.ply", "ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n"), {"line 3", "unknown PLY header keyword"});
  expect_soup_error(write_file("flist.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                            "element face 1\nproperty list float int vertex_indices\nend_header\n" + body),
                    {"line 8", "integer type"});
  expect_soup_error(write_file("fidx.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                           "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + body),
                    {"line 7", "integer type"});
  expect_soup_error(write_file("noz.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                          "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + body),
                    {"line 3", "no property 'z'"});
  expect_soup_error(write_file("noface.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                             "end_header\n0 0 0\n1 0 0\n0 1 0\n"),
                    {"no 'face' element"});
  expect_soup_error(write_file("nolist.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                             "element face 1\nproperty int vertex_indices\nend_header\n" + body),
                    {"line 7", "no list property 'vertex_indices'"});
  expect_soup_error(write_file("neglen.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                             "element face 1\nproperty list char int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n"),
                    {"line 13", "invalid list length"});
}

TEST(FileErrors, OffHeaderProblems) {
  expect_soup_error(write_file("4off.off", "4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n"), {"line 1", "not supported"});
  expect_soup_error(write_file("bin.off", "OFF BINARY\n"), {"line 1", "binary OFF"});
  expect_soup_error(write_file("xoff.off", "XOFF\n3 1 0\n"), {"line 1", "unknown OFF header keyword"});
  expect_soup_error(write_file("cnt.off", "OFF\n3\n0 0 0\n"), {"line 2", "expected 'vertex_count face_count"});
  expect_soup_error(write_file("zero.off", "OFF\n0 0 0\n"), {"line 2", "0 vertices"});
  expect_soup_error(write_file("onlyhdr.off", "OFF\n# counts missing\n"), {"before the vertex and face counts"});
  // No keyword: counts directly (tolerated).
  EXPECT_EQ(crossparam::read_polygon_soup(write_file("nokw.off", off_text(tetrahedron()).substr(4))).polygons.size(), 4u);
}

// ================================================================================================ mesh checks

TEST(MeshCheck, NonTriangleFace) {
  Soup cube;
  cube.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  cube.polygons = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  expect_mesh_error(write_file("cube.off", off_text(cube)), {"face 0 has 4 vertices", "non-triangle"});
  expect_mesh_error(write_file("cube.obj", obj_text(cube)), {"face 0 has 4 vertices", "non-triangle"});
}

TEST(MeshCheck, OpenMesh) {
  Soup s = octahedron();
  s.polygons.pop_back();
  expect_mesh_error(write_file("open.off", off_text(s)), {"open", "3 boundary edges", "edge (0, 3)"});
}

TEST(MeshCheck, NonManifoldEdge) {
  Soup s = octahedron();
  s.points.push_back({1, 1, 0});
  s.polygons.push_back({0, 6, 2});
  expect_mesh_error(write_file("nme.off", off_text(s)), {"non-manifold edge (0, 2)", "3 faces"});
}

TEST(MeshCheck, NonManifoldVertex) {
  // Two tetrahedra touching at one vertex (an hourglass): closed and edge-manifold, but vertex 0 has two fans.
  Soup b = tetrahedron();
  for (auto& p : b.points) p = {-p[0], -p[1], -p[2]};
  const Soup s = join(tetrahedron(), b, 1);
  expect_mesh_error(write_file("nmv.off", off_text(s)), {"non-manifold vertex 0", "more than one fan"});
}

TEST(MeshCheck, SeveralComponents) {
  const Soup s = join(join(tetrahedron(), tetrahedron(5)), octahedron());
  expect_mesh_error(write_file("comp.off", off_text(s)), {"3 connected components"});
}

TEST(MeshCheck, DegenerateDuplicateAndUnused) {
  Soup s = octahedron();
  s.polygons[5] = {1, 2, 1};
  expect_soup_mesh_error(s, {"face 5 is degenerate", "vertex 1 twice"});
  s = octahedron();
  s.polygons.push_back({4, 0, 2});
  expect_soup_mesh_error(s, {"faces 0 and 8 are duplicate faces"});
  s = octahedron();
  s.points.push_back({5, 5, 5});
  expect_soup_mesh_error(s, {"vertex 6 is not used by any face"});
  s = octahedron();
  s.polygons[2] = {1, 3, 9};
  expect_soup_mesh_error(s, {"face 2 refers to vertex 9", "out of range"});
  s = octahedron();
  s.points[3][0] = std::numeric_limits<double>::quiet_NaN();
  expect_soup_mesh_error(s, {"vertex 3", "non-finite"});
  s = octahedron();
  s.points[3][0] = -1e200;
  expect_soup_mesh_error(s, {"vertex 3", "out of supported range"});
  expect_soup_mesh_error(Soup{}, {"no faces"});
}

TEST(MeshCheck, NonOrientableSurface) {
  // The 6-vertex real projective plane: closed, manifold, connected, not orientable.
  Soup s;
  for (int i = 0; i < 6; ++i) s.points.push_back({std::cos(i * 1.0), std::sin(i * 1.0), i * 0.1});
  s.polygons = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 1}, {1, 2, 4}, {2, 3, 5}, {3, 4, 1}, {4, 5, 2}, {5, 1, 3}};
  expect_mesh_error(write_file("rp2.off", off_text(s)), {"not orientable"});
}

TEST(MeshCheck, ZeroAreaAndNeedleTrianglesAreValid) {
  // A completely flat "tetrahedron" (all faces zero-area or folded) is combinatorially a valid sphere.
  Soup s = tetrahedron();
  s.points[3] = {0.25, 0.25, 0};
  Mesh m;
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(s, m, "flat").genus, 0);
  s = octahedron();
  s.points[4] = {0, 0, 1e-12};  // needles
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(s, m, "needle").genus, 0);
}

TEST(MeshCheck, InconsistentOrientationIsRepairedWithWarning) {
  const Soup oct = octahedron();
  Soup s = oct;
  std::swap(s.polygons[2][1], s.polygons[2][2]);
  const std::string path = write_file("flip1.off", off_text(s));
  Mesh m;
  const auto r = crossparam::read_triangle_mesh(path, m);
  EXPECT_EQ(r.reoriented_faces, 1u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("reoriented 1 of 8 faces"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find(path), std::string::npos);
  EXPECT_EQ(r.genus, 0);
  expect_mesh_equals_soup(m, oct);  // vertex order unchanged, face 2 back to the majority orientation

  // Flip 5 of 8: the 3 others are flipped instead, and the result is the flipped orientation.
  s = oct;
  for (int f = 0; f < 5; ++f) std::swap(s.polygons[f][1], s.polygons[f][2]);
  const auto r2 = crossparam::soup_to_triangle_mesh(s, m, "flip5");
  EXPECT_EQ(r2.reoriented_faces, 3u);
  Soup reversed = oct;
  for (auto& p : reversed.polygons) std::swap(p[1], p[2]);
  expect_mesh_equals_soup(m, reversed);

  // Face 0 flipped alone: it is the BFS root, but still the minority.
  s = oct;
  std::swap(s.polygons[0][1], s.polygons[0][2]);
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(s, m, "flip0").reoriented_faces, 1u);
  expect_mesh_equals_soup(m, oct);
}

TEST(MeshCheck, PolyhedronWithIdsLoadsInFileOrder) {
  const Soup oct = octahedron();
  const std::string path = write_file("poly.off", off_text(oct));
  Polyhedron p;
  const auto r = crossparam::read_triangle_mesh(path, p);
  EXPECT_EQ(r.genus, 0);
  ASSERT_EQ(num_vertices(p), 6u);
  EXPECT_EQ(mesh_points(p), oct.points);
  const auto fs = mesh_faces(p);
  ASSERT_EQ(fs.size(), oct.polygons.size());
  for (std::size_t f = 0; f < fs.size(); ++f) EXPECT_TRUE(same_oriented(fs[f], oct.polygons[f]));
  std::size_t i = 0;
  for (auto v : vertices(p)) EXPECT_EQ(v->id(), i++);
  i = 0;
  for (auto f : faces(p)) EXPECT_EQ(f->id(), i++);
  EXPECT_EQ(crossparam::check_triangle_mesh(p, "poly").genus, 0);
  // Loading again into the non-empty polyhedron replaces it.
  crossparam::read_triangle_mesh(write_file("torus.off", off_text(torus())), p);
  EXPECT_EQ(num_vertices(p), torus().points.size());
  EXPECT_EQ(crossparam::check_triangle_mesh(p, "poly").genus, 1);
  // Writing a polyhedron keeps the order.
  const std::string out = (temp_dir() / "poly_out.off").string();
  crossparam::write_off(out, p);
  const Soup back = crossparam::read_polygon_soup(out);
  EXPECT_EQ(back.points, torus().points);
  EXPECT_EQ(back.polygons, torus().polygons);
  // A polyhedron without ids works too.
  Plain_polyhedron q;
  EXPECT_EQ(crossparam::read_triangle_mesh(path, q).genus, 0);
  EXPECT_EQ(crossparam::check_triangle_mesh(q, "plain").genus, 0);
}

TEST(MeshCheck, GenusOfGeneratedAndRealMeshes) {
  Mesh m;
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(octahedron(), m, "oct").genus, 0);
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(tetrahedron(), m, "tet").genus, 0);
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(torus(), m, "torus").genus, 1);
  EXPECT_EQ(crossparam::check_triangle_mesh(m, "torus").genus, 1);
  const fs::path knot = fs::path(CROSSPARAM_SHARED_DIR) / "data/models/cgal/knot.off";
  if (!fs::exists(knot)) GTEST_SKIP() << "knot.off not found at " << knot << " (shared data absent)";
  const auto r = crossparam::read_triangle_mesh(knot.string(), m);
  EXPECT_EQ(r.genus, 1);
  EXPECT_EQ(num_vertices(m), 2080u);
  EXPECT_EQ(num_faces(m), 4160u);
}

TEST(MeshCheck, RealModelsLoadWithDocumentedGenus) {
  if (!shared_dir_present()) GTEST_SKIP() << "shared data directory " << CROSSPARAM_SHARED_DIR << "/data is absent";
  const fs::path models = fs::path(CROSSPARAM_SHARED_DIR) / "data/models";
  const std::vector<std::pair<std::string, int>> expected = {
      {"cgal/triceratops.off", 0}, {"cgal/knot.off", 1}, {"cgal/eight.off", 2}, {"cgal/homer.off", 0},
      {"cgal/hand.off", 0}, {"libigl-tutorial-data/cow.off", 0}, {"libigl-tutorial-data/fertility.off", 4},
      {"libigl-tutorial-data/decimated-max.obj", 0}, {"libigl-tutorial-data/elephant.obj", 0},
      {"libigl-tutorial-data/3holes.off", 3}, {"libigl-tutorial-data/bunny.off", 0},
      {"common-3d-test-models/horse.ply", 0}, {"keenan-crane/spot_triangulated.obj", 0},
      {"keenan-crane/blub_triangulated.obj", 0}, {"keenan-crane/bob_small.ply", 1}, {"feline/feline.obj", 2}};
  for (const auto& e : expected) {
    const fs::path p = models / e.first;
    if (!fs::exists(p)) {
      std::cout << "[ note ] missing " << p << "\n";
      continue;
    }
    Mesh m;
    try {
      const auto r = crossparam::read_triangle_mesh(p.string(), m);
      EXPECT_EQ(r.genus, e.second) << p;
      EXPECT_EQ(crossparam::check_triangle_mesh(m, p.string()).genus, e.second) << p;
      if (r.reoriented_faces > 0) std::cout << "[ note ] " << r.warnings[0] << "\n";
    } catch (const std::exception& ex) {
      ADD_FAILURE() << ex.what();
    }
  }
  // Documented invalid ones.
  expect_mesh_error((models / "libigl-tutorial-data/camelhead.off").string(), {"open"});
  expect_mesh_error((models / "cgal/double-torus-example.off").string(), {"non-triangle"});
}

TEST(MeshCheck, CheckTriangleMeshOnUserBuiltMeshes) {
  Mesh m;
  crossparam::soup_to_triangle_mesh(octahedron(), m, "oct");
  EXPECT_EQ(crossparam::check_triangle_mesh(m, "oct").genus, 0);

  Mesh open = m;
  CGAL::Euler::remove_face(halfedge(*faces(open).begin(), open), open);
  expect_error([&] { crossparam::check_triangle_mesh(open, "user"); }, {"user: ", "open", "3 boundary edges"});

  Mesh iso = m;
  iso.add_vertex(crossparam::Point_3(3, 3, 3));
  expect_error([&] { crossparam::check_triangle_mesh(iso, "user"); }, {"vertex 6 is isolated"});

  Mesh garbage = iso;  // removed elements must not confuse the checks
  garbage.remove_vertex(*std::prev(vertices(garbage).end()));
  ASSERT_TRUE(garbage.has_garbage());
  EXPECT_EQ(crossparam::check_triangle_mesh(garbage, "garbage").genus, 0);

  Mesh nan = m;
  nan.point(*vertices(nan).begin()) = crossparam::Point_3(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  expect_error([&] { crossparam::check_triangle_mesh(nan, "user"); }, {"vertex 0", "non-finite"});
  nan.point(*vertices(nan).begin()) = crossparam::Point_3(1e120, 0, 0);
  expect_error([&] { crossparam::check_triangle_mesh(nan, "user"); }, {"vertex 0", "out of supported range"});

  Mesh two;
  crossparam::soup_to_triangle_mesh(tetrahedron(), two, "t");
  {
    Mesh other;
    crossparam::soup_to_triangle_mesh(tetrahedron(3), other, "t");
    two.join(other);
  }
  expect_error([&] { crossparam::check_triangle_mesh(two, "user"); }, {"2 connected components"});

  // Hourglass: two tetrahedra, then the apex of the second is merged into vertex 0 of the first.
  Mesh pinched;
  {
    Soup b = tetrahedron();
    for (auto& p : b.points) p = {-p[0], -p[1], -p[2]};
    crossparam::soup_to_triangle_mesh(tetrahedron(), pinched, "one");
    Mesh second;
    crossparam::soup_to_triangle_mesh(b, second, "two");
    pinched.join(second);
    const Mesh::Vertex_index v0(0), v4(4);
    for (auto h : halfedges(pinched))
      if (target(h, pinched) == v4) pinched.set_target(h, v0);
    pinched.remove_vertex(v4);
  }
  expect_error([&] { crossparam::check_triangle_mesh(pinched, "user"); }, {"non-manifold vertex 0"});

  Mesh quad;
  {
    std::vector<Mesh::Vertex_index> v;
    for (int i = 0; i < 4; ++i) v.push_back(quad.add_vertex(crossparam::Point_3(i % 2, i / 2, 0)));
    quad.add_face(v[0], v[1], v[3], v[2]);
  }
  expect_error([&] { crossparam::check_triangle_mesh(quad, "user"); }, {"face 0 has 4 vertices"});
  expect_error([&] { crossparam::check_triangle_mesh(Mesh(), "user"); }, {"no faces"});
}

// ================================================================================================ shared data

TEST(SharedData, EveryNastyFileThrowsInputErrorOrLoads) {
  const fs::path nasty = fs::path(CROSSPARAM_SHARED_DIR) / "data/nasty";
  if (!fs::is_directory(nasty)) GTEST_SKIP() << "shared nasty data directory " << nasty << " is absent";
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(nasty)) {
    if (!e.is_regular_file()) continue;
    const std::string ext = crossparam::internal::soup_io::to_lower(e.path().extension().string());
    if (ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  EXPECT_GE(files.size(), 20u);
  for (const fs::path& f : files) {
    Mesh m;
    try {
      const auto r = crossparam::read_triangle_mesh(f.string(), m);
      std::cout << "[ loads ] " << f.lexically_relative(nasty).string() << ": genus " << r.genus << "\n";
    } catch (const Input_error& e) {
      const std::string msg = e.what();
      EXPECT_GT(msg.size(), f.string().size() + 2) << f;
      EXPECT_EQ(msg.rfind(f.string() + ": ", 0), 0u) << msg;
      std::cout << "[ rejected ] " << msg.substr(nasty.string().size() + 1) << "\n";
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": unexpected exception type: " << e.what();
    }
  }
  // The documented defects are the ones reported.
  auto path = [&](const char* rel) { return (nasty / rel).string(); };
  expect_mesh_error(path("common-3d-test-models/cow.obj"), {"non-manifold vertex"});
  expect_mesh_error(path("geometry-central/hourglass_ico.obj"), {"non-manifold vertex"});
  expect_mesh_error(path("cgal/cubes.off"), {"non-manifold edge"});
  expect_mesh_error(path("geometry-central/fan3.obj"), {"non-manifold edge"});
  expect_mesh_error(path("geometry-central/lego.ply"), {"open"});
  expect_mesh_error(path("cgal/degtri_four.off"), {"open"});
  expect_mesh_error(path("geometry-central/platonic_shelf.obj"), {"non-triangle"});
}

TEST(SharedData, CgalIoCrashersAreRejectedCleanly) {
  const fs::path dir = fs::path(CROSSPARAM_SHARED_DIR) / "data/nasty/cgal-io-crashers";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "shared directory " << dir << " is absent";
  for (const char* name : {"coff_short_color_heap_overflow.off", "off_negative_color_index.off",
                           "ply_binary_huge_alloc.ply", "ply_property_before_element.ply"}) {
    const std::string p = (dir / name).string();
    ASSERT_TRUE(fs::exists(p)) << p;
    Allocation_watch watch;
    const std::string msg = expect_soup_error(p, {});
    EXPECT_LT(watch.largest(), std::size_t(1) << 20) << msg;
    std::cout << "[ rejected ] " << msg.substr(dir.string().size() + 1) << "\n";
    // The files start with a stray byte; without it they reach the defects they were made for.
    const std::string stripped = write_file(std::string("stripped_") + name, read_file(p).substr(1));
    Allocation_watch watch2;
    const std::string msg2 = expect_soup_error(stripped, {});
    EXPECT_LT(watch2.largest(), std::size_t(1) << 20) << msg2;
    std::cout << "[ rejected ] " << msg2.substr(temp_dir().string().size() + 1) << "\n";
  }
}

// ================================================================================================ features

namespace {
Feature_correspondence read_features(const std::string& name, const std::string& text, std::size_t ns = 10,
                                     std::size_t nt = 20) {
  return crossparam::read_feature_pairs(write_file(name, text), ns, nt);
}
} // namespace

TEST(Features, ValidFileWithCommentsAndBlankLines) {
  const auto fc = read_features("ok.txt", "# source target\n\n0 5\r\n3 7 # trailing comment\n  9\t19\n\n2 0\n# end\n");
  ASSERT_EQ(fc.size(), 4u);
  EXPECT_EQ(fc[0], (crossparam::Feature_pair{0, 5}));
  EXPECT_EQ(fc[1], (crossparam::Feature_pair{3, 7}));
  EXPECT_EQ(fc[2], (crossparam::Feature_pair{9, 19}));
  EXPECT_EQ(fc[3], (crossparam::Feature_pair{2, 0}));
}

TEST(Features, MalformedLines) {
  for (const std::string bad : {"3 x", "1.5 2", "-1 3", "1 2 3", "7", "0x1 2", "1,2", "1e3 2", "99999999999999999999999 1"}) {
    const std::string path = write_file("bad.txt", "0 0\n# c\n" + bad + "\n1 1\n2 2\n3 3\n");
    expect_error<Feature_error>([&] { crossparam::read_feature_pairs(path, 10, 20); },
                                {path + ": line 3: ", "malformed", "two non-negative integers"});
  }
}

// The features of N meshes (read_multi_features): one column per mesh, or the columns chosen.
TEST(Features, MultiColumnFiles) {
  const std::vector<std::size_t> counts{10, 20, 30};
  const std::string ok = write_file("multi.txt", "\xEF\xBB\xBF# three meshes\n0 5 29\r\n\n3 7 1 # comment\n9\t19 0\n");
  const Multi_feature_correspondence fc = crossparam::read_multi_features(ok, counts);
  ASSERT_EQ(fc.size(), 3u);
  EXPECT_EQ(fc[0], (std::vector<std::size_t>{0, 5, 29}));
  EXPECT_EQ(fc[2], (std::vector<std::size_t>{9, 19, 0}));
  // Columns chosen: the third and the first of a file for three meshes, for two meshes of 30 and 10 vertices.
  const Multi_feature_correspondence two = crossparam::read_multi_features(ok, {30, 10}, {2, 0});
  ASSERT_EQ(two.size(), 3u);
  EXPECT_EQ(two[1], (std::vector<std::size_t>{1, 3}));
  const auto bad = [&](const std::string& text, std::initializer_list<std::string> parts, std::vector<std::size_t> columns = {}) {
    const std::string path = write_file("multibad.txt", text);
    expect_error<Feature_error>([&] { crossparam::read_multi_features(path, counts, columns); }, parts);
  };
  bad("0 0 0\n1 1\n2 2 2\n", {": line 2: ", "2 vertices where 3 are needed"});
  bad("0 0 0 0\n1 1 1\n2 2 2\n", {": line 1: ", "4 vertices where 3"});
  bad("0 0 0\n1 x 1\n2 2 2\n", {": line 2: ", "'x' is not a vertex index"});
  bad("0 0 0\n1 -1 1\n2 2 2\n", {": line 2: ", "not a vertex index"});
  bad("0 0 0\n1 1 30\n2 2 2\n", {": line 2: ", "vertex 30 of mesh 2, which has 30 vertices"});
  bad("0 0 0\n\n1 1 1\n2 1 2\n", {": line 4: ", "vertex 1 of mesh 1 is a duplicate", "line 3"});
  bad("0 0 0\n1 1 1\n", {"at least three features are needed, found 2"});
  bad("0 0 0\n1 1 1\n2 2 2\n", {"2 columns chosen for 3 meshes"}, {0, 1});
  bad("0 0 0\n1 1 1\n2 2 2\n", {": line 1: ", "3 vertices where at least 4"}, {0, 1, 3});
  expect_error<Feature_error>([&] { crossparam::read_multi_features((temp_dir() / "nope.txt").string(), counts); }, {"does not exist"});
}

TEST(Features, OutOfRangeDuplicatesAndTooFew) {
  const std::string p1 = write_file("range.txt", "0 0\n1 1\n10 2\n3 3\n");
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(p1, 10, 20); },
                              {p1 + ": line 3: ", "source vertex 10", "out of range", "source mesh has 10 vertices"});
  const std::string p2 = write_file("range2.txt", "0 0\n1 25\n2 2\n3 3\n");
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(p2, 10, 20); },
                              {p2 + ": line 2: ", "target vertex 25", "out of range", "target mesh has 20 vertices"});
  const std::string p3 = write_file("dup.txt", "0 0\n4 1\n\n2 2\n4 3\n5 5\n");
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(p3, 10, 20); },
                              {p3 + ": line 5: ", "source vertex 4", "line 2", "duplicate"});
  const std::string p4 = write_file("dupt.txt", "0 0\n1 1\n2 7\n3 7\n");
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(p4, 10, 20); },
                              {p4 + ": line 4: ", "target vertex 7", "line 3", "duplicate"});
  const std::string p5 = write_file("few.txt", "0 0\n1 1\n2 2\n");
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(p5, 10, 20); }, {p5 + ": ", "only 3 features", "at least 4"});
  const std::string p6 = write_file("none.txt", "# nothing\n");
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(p6, 10, 20); }, {"only 0 features"});
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs((temp_dir() / "nope.txt").string(), 10, 20); }, {"does not exist"});
  expect_error<Feature_error>([&] { crossparam::read_feature_pairs(write_file("empty.txt", ""), 10, 20); }, {"empty"});

  // The same checks for library users, naming feature indices.
  Feature_correspondence fc = {{0, 0}, {1, 1}, {2, 2}, {1, 3}};
  expect_error<Feature_error>([&] { crossparam::validate_feature_pairs(fc, 10, 20, "ctx"); },
                              {"ctx: feature 3: ", "source vertex 1", "feature 1"});
  fc[3] = {3, 30};
  expect_error<Feature_error>([&] { crossparam::validate_feature_pairs(fc, 10, 20, "ctx"); },
                              {"ctx: feature 3: ", "target vertex 30", "out of range"});
  fc[3] = {3, 3};
  EXPECT_NO_THROW(crossparam::validate_feature_pairs(fc, 10, 20, "ctx"));
  fc.pop_back();
  expect_error<Feature_error>([&] { crossparam::validate_feature_pairs(fc, 10, 20, "ctx"); }, {"only 3 features"});
}

// ================================================================================================ entry-point checks

TEST(EntryChecks, ValidationStandsApartFromIo) {
  // validation.h is included first above and includes no I/O header: its guard is set, io.h's readers come
  // from io.h alone.
#ifndef CROSSPARAM_VALIDATION_H
  ADD_FAILURE() << "validation.h not included";
#endif
  Mesh m;
  EXPECT_EQ(crossparam::soup_to_triangle_mesh(octahedron(), m, "oct").genus, 0);
  EXPECT_EQ(crossparam::check_triangle_mesh(m, "oct").genus, 0);
}

TEST(EntryChecks, LayoutInputsInOrderWithTheirMessages) {
  // internal::check_layout_inputs is what compute_patch_layouts and the Cross_parameterization constructor run
  // once: meshes (source first), genus, features, bounding boxes.
  const auto np = crossparam::parameters::default_values();
  Mesh oct, tet, tor, flat, open;
  crossparam::soup_to_triangle_mesh(octahedron(), oct, "oct");
  crossparam::soup_to_triangle_mesh(tetrahedron(), tet, "tet");
  crossparam::soup_to_triangle_mesh(torus(), tor, "torus");
  Soup point = tetrahedron();
  for (auto& p : point.points) p = {1, 2, 3};
  crossparam::soup_to_triangle_mesh(point, flat, "point"); // valid connectivity, all corners at one point
  open = oct;
  CGAL::Euler::remove_face(halfedge(*faces(open).begin(), open), open);
  const Feature_correspondence f4 = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  EXPECT_NO_THROW(crossparam::internal::check_layout_inputs(oct, tet, f4, np, np));
  expect_error([&] { crossparam::internal::check_layout_inputs(open, open, f4, np, np); }, {"source mesh: ", "open"});
  expect_error([&] { crossparam::internal::check_layout_inputs(oct, open, f4, np, np); }, {"target mesh: ", "open"});
  expect_error<crossparam::Incompatible_inputs_error>(
      [&] { crossparam::internal::check_layout_inputs(oct, tor, f4, np, np); },
      {"the source mesh has genus 0 but the target mesh has genus 1"});
  expect_error<Feature_error>([&] { crossparam::internal::check_layout_inputs(tor, tor, {}, np, np); },
                              {"feature correspondence: only 0 features"});
  expect_error<Feature_error>([&] { crossparam::internal::check_layout_inputs(oct, tet, {{0, 0}}, np, np); },
                              {"feature correspondence: only 1 feature given"});
  expect_error<Feature_error>([&] { crossparam::internal::check_layout_inputs(flat, flat, {}, np, np); },
                              {"feature correspondence: only 0 features"});
  expect_error([&] { crossparam::internal::check_layout_inputs(oct, flat, f4, np, np); },
               {"mesh has a degenerate bounding box"});
}

TEST(EntryChecks, InnerEntryPointsSkipTheirChecks) {
  namespace cp = crossparam;
  EXPECT_FALSE(cp::internal::are_inputs_checked(cp::parameters::default_values()));
  EXPECT_TRUE(cp::internal::are_inputs_checked(cp::internal::inputs_checked(cp::parameters::default_values())));
  EXPECT_TRUE(cp::internal::are_inputs_checked(
      cp::parameters::apply_smoothing(false, cp::internal::inputs_checked(cp::parameters::default_values()))));
}

TEST(EntryChecks, CompatibleSoups) {
  const Soup a = octahedron();
  EXPECT_NO_THROW(crossparam::check_compatible(a, a));
  Soup b = a;
  b.points.pop_back();
  expect_error<crossparam::Incompatible_inputs_error>([&] { crossparam::check_compatible(a, b, "a.off", "b.off"); },
                                                      {"a.off and b.off are not compatible: 6 vs 5 vertices"});
  b = a;
  std::swap(b.polygons[3][0], b.polygons[3][1]);
  expect_error<crossparam::Incompatible_inputs_error>([&] { crossparam::check_compatible(a, b); },
                                                      {"A and B are not compatible: face 3 has different vertices"});
}

// ================================================================================================ writing

TEST(Write, AtomicWriteLeavesNoFileWhenTheWriterThrows) {
  const fs::path dir = temp_dir() / "atomic";
  fs::create_directories(dir);
  const std::string path = (dir / "out.off").string();
  struct Boom {};
  EXPECT_THROW(crossparam::write_file_atomically(path, [](std::ostream& os) {
                 os << "partial";
                 throw Boom{};
               }),
               Boom);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir)) << "temporary file left behind";

  crossparam::write_file_atomically(path, [](std::ostream& os) { os << 0.1; });
  EXPECT_EQ(read_file(path), "0.10000000000000001");  // precision 17 by default
  EXPECT_THROW(crossparam::write_file_atomically(path, [](std::ostream&) { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_EQ(read_file(path), "0.10000000000000001");  // the old file is untouched
  std::size_t n_files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++n_files;
  }
  EXPECT_EQ(n_files, 1u);

  expect_error([&] { crossparam::write_file_atomically((dir / "no/such/dir/x.off").string(), [](std::ostream&) {}); },
               {"cannot write", "does not exist"});
  expect_error([&] { crossparam::write_file_atomically(dir.string(), [](std::ostream&) {}); }, {"directory"});
  if (fs::is_directory("/proc"))  // not writable, even for root
    expect_error([&] { crossparam::write_file_atomically("/proc/crossparam_test.off", [](std::ostream&) {}); },
                 {"/proc/crossparam_test.off: cannot write"});
}

TEST(Write, OffAndPlyRoundTripExactly) {
  Soup s = torus();
  s.points[0] = {0.1, 1.0 / 3.0, -2.5e-7};
  std::vector<std::array<std::size_t, 3>> tris;
  for (const auto& p : s.polygons) tris.push_back({p[0], p[1], p[2]});
  const std::string off = (temp_dir() / "w.off").string();
  crossparam::write_off(off, s.points, tris);
  Soup back = crossparam::read_polygon_soup(off);
  EXPECT_EQ(back.points, s.points);
  EXPECT_EQ(back.polygons, s.polygons);

  std::vector<std::array<unsigned char, 3>> fcol(tris.size(), {255, 0, 10});
  const std::string ply = (temp_dir() / "w.ply").string();
  crossparam::write_ply_colored(ply, s.points, tris, fcol);
  back = crossparam::read_polygon_soup(ply);
  EXPECT_EQ(back.points, s.points);
  EXPECT_EQ(back.polygons, s.polygons);
  EXPECT_NE(read_file(ply).find("property list uchar uint vertex_indices\nproperty uchar red"), std::string::npos);
  EXPECT_NE(read_file(ply).find(" 255 0 10\n"), std::string::npos);

  std::vector<std::array<unsigned char, 3>> vcol(s.points.size(), {1, 2, 3});
  const std::string vply = (temp_dir() / "wv.ply").string();
  crossparam::write_ply_vertex_colored(vply, s.points, tris, vcol);
  back = crossparam::read_polygon_soup(vply);
  EXPECT_EQ(back.points, s.points);
  EXPECT_EQ(back.polygons, s.polygons);
  EXPECT_NE(read_file(vply).find("property double z\nproperty uchar red"), std::string::npos);

  Mesh m;
  crossparam::soup_to_triangle_mesh(s, m, "torus");
  const std::string moff = (temp_dir() / "m.off").string();
  crossparam::write_off(moff, m);
  back = crossparam::read_polygon_soup(moff);
  EXPECT_EQ(back.points, s.points);
  EXPECT_EQ(back.polygons, s.polygons);

  // Bad input to the writers.
  fcol.pop_back();
  EXPECT_THROW(crossparam::write_ply_colored(ply, s.points, tris, fcol), crossparam::Error);
  tris[0][0] = 1000;
  EXPECT_THROW(crossparam::write_off(off, s.points, tris), crossparam::Error);
}

// ================================================================================================ fuzzing

TEST(Fuzz, MutatedFilesOnlyEverThrowInputError) {
  const Soup oct = octahedron();
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"f.off", off_text(oct)},          {"f.obj", obj_text(oct)},          {"f.ply", ply_ascii_text(oct)},
      {"fb.ply", ply_binary(oct, false)}, {"fbb.ply", ply_binary(oct, true)}, {"f.stl", stl_ascii_text(oct)},
      {"fb.stl", stl_binary(oct)}};
  // CROSSPARAM_FUZZ_ITERATIONS=N runs N mutations per seed file (default 300), e.g. under sanitizers.
  const char* env = std::getenv("CROSSPARAM_FUZZ_ITERATIONS");
  const int iterations = env ? std::max(1, std::atoi(env)) : 300;
  std::mt19937 rng(12345);
  std::size_t loaded = 0, rejected = 0;
  Allocation_watch watch;
  for (const auto& seed : seeds) {
    for (int iter = 0; iter < iterations; ++iter) {
      std::string data = seed.second;
      const int kind = iter % 4;
      const int n_mut = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < n_mut && !data.empty(); ++k) {
        const std::size_t pos = rng() % data.size();
        if (kind == 0) data[pos] = static_cast<char>(rng() % 256);
        else if (kind == 1) data[pos] = "0123456789-+.e \n#/x"[rng() % 19];
        else if (kind == 2) data.erase(pos, 1 + rng() % 8);
        else data.resize(pos);
      }
      const std::string path = write_file("fuzz_" + seed.first, data);
      try {
        Mesh m;
        crossparam::read_triangle_mesh(path, m);
        ++loaded;
      } catch (const Input_error& e) {
        ++rejected;
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << seed.first << " iteration " << iter << ": unexpected exception " << e.what();
      }
    }
  }
  EXPECT_GT(rejected, 0u);
  EXPECT_GT(loaded, 0u);
  EXPECT_LT(watch.largest(), std::size_t(16) << 20);
  std::cout << "[ fuzz ] " << loaded << " mutated files loaded, " << rejected << " rejected\n";
}
