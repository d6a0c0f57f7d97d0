// SPDX-License-Identifier: GPL-3.0-or-later
// Example 05: a user-written weights policy for the smoothing of the map (paper §4.2).
//
//   example_05_smoothing_weights        two generated creatures
//
// The smoothing moves every vertex of each parameterization to a weighted average of its neighbours; the
// weights are a policy, a model of the SmoothingWeights concept:
//   void prepare(const Refined_mesh& m)         called once with the mesh, before the smoothing;
//   double operator()(Refined_halfedge h) const  the weight of target(h) in the average for source(h), positive.
// The default, Mean_value_weights, preserves the shape of the mesh. This example writes a policy of its own,
// inverse edge lengths (near neighbours pull harder), and compares the distortion of the two maps.
#include <crossparam/cross_parameterization.h>
#include <support/shapes.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <vector>

using Surface_mesh = crossparam::Surface_mesh;
using Map = crossparam::Cross_parameterization<Surface_mesh, Surface_mesh>;

/// A model of SmoothingWeights: the weight of an edge is the inverse of its length on the mesh as given.
class Inverse_length_weights {
public:
  using Mesh = crossparam::Refined_mesh;
  using Halfedge = crossparam::Refined_halfedge;

  void prepare(const Mesh& m) {
    weight_.assign(m.number_of_halfedges(), 0.0);
    for (Halfedge h : m.halfedges()) {
      const double length = std::sqrt(CGAL::squared_distance(m.point(m.source(h)), m.point(m.target(h))));
      // An edge of zero length would get an infinite weight; the smallest positive double keeps it finite.
      weight_[std::size_t(h)] = 1.0 / std::max(length, std::numeric_limits<double>::min());
    }
  }
  double operator()(Halfedge h) const { return weight_[std::size_t(h)]; }

private:
  std::vector<double> weight_;
};

void report(const char* name, const Map& map) {
  const auto& s = map.statistics();
  std::cout << name << ": angular distortion " << s.distortion_initial.angular << " before smoothing, "
            << s.distortion.angular << " after (L2 stretch " << s.distortion.l2_stretch << "); "
            << s.smoothing_best_iteration << " passes kept; certified one-to-one: "
            << (map.certificate(crossparam::Mesh_side::source).valid && map.certificate(crossparam::Mesh_side::target).valid ? "yes" : "no") << "\n";
}

int main() try {
  const Surface_mesh a = crossparam::shapes::creature_a(), b = crossparam::shapes::creature_b();
  const crossparam::Feature_correspondence features = crossparam::shapes::creature_features(a, b);

  Surface_mesh s1 = a, t1 = b; // each map refines its own copies
  const Map mean_value(s1, t1, features);
  report("mean-value weights (default)", mean_value);

  Surface_mesh s2 = a, t2 = b;
  const Map inverse_length(s2, t2, features, crossparam::parameters::smoothing_weights(Inverse_length_weights()));
  report("inverse-length weights       ", inverse_length);
  return mean_value.certificate(crossparam::Mesh_side::source).valid && inverse_length.certificate(crossparam::Mesh_side::source).valid ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}
