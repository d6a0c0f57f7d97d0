// SPDX-License-Identifier: GPL-3.0-or-later
// Patch layouts on the real bench cases in ../shared/bench (skipped with a message when it is absent).
#include <crossparam/io.h>
#include <crossparam/patch_layout.h>

#include "bench_cases.h"

#include <gtest/gtest.h>

using namespace crossparam;

namespace {

class BenchLayout : public ::testing::TestWithParam<std::string> {};

TEST_P(BenchLayout, VerifiedLayouts) {
  std::optional<test_bench::Case> c = test_bench::load(GetParam());
  if (!c) GTEST_SKIP() << test_bench::absent(GetParam());
  Surface_mesh &s = c->source, &t = c->target;
  const Feature_correspondence& f = c->features;
  const std::size_t ns = s.number_of_vertices(), nt = t.number_of_vertices();
  Surface_mesh s0 = s, t0 = t;
  Patch_layout L = compute_patch_layouts(s, t, f);
  Layout_verification check = verify_patch_layouts(s, t, L);
  ASSERT_TRUE(check.valid) << check.message;
  EXPECT_EQ(L.base_triangles.size(), 2 * f.size() - 4);
  EXPECT_EQ(L.base_edges.size(), 3 * f.size() - 6);
  EXPECT_EQ(s.number_of_vertices(), ns + L.source.splits.size());
  EXPECT_EQ(t.number_of_vertices(), nt + L.target.splits.size());
  for (auto v : s0.vertices()) ASSERT_EQ(s0.point(v), s.point(v));
  for (auto v : t0.vertices()) ASSERT_EQ(t0.point(v), t.point(v));
  for (std::size_t k = 0; k < f.size(); ++k) {
    EXPECT_EQ(L.source.feature_vertices[k], f[k].source);
    EXPECT_EQ(L.target.feature_vertices[k], f[k].target);
  }
  // Real, near-isometric cases: refinement stays small compared with the meshes.
  EXPECT_LT(L.source.splits.size(), ns / 10) << "source splits";
  EXPECT_LT(L.target.splits.size(), nt / 10) << "target splits";
  RecordProperty("splits_source", int(L.source.splits.size()));
  RecordProperty("splits_target", int(L.target.splits.size()));
}

INSTANTIATE_TEST_SUITE_P(Shared, BenchLayout, ::testing::ValuesIn(test_bench::names()),
                         [](const auto& info) { return info.param; });

} // namespace
