// SPDX-License-Identifier: GPL-3.0-or-later
// Example 08: one connectivity for three models (paper §2.3) and blends of them.
//
//   example_08_many_models        three generated creatures
//
// The three creatures share eleven features (nose, head, feet, tail, back, belly, chest, flanks). The first is the
// source: it is mapped onto the two others, remeshed compatibly with the second, and the common mesh is then
// refined until it approximates the third too. The example checks that the outputs share one face list and prints
// the independent verifier's verdict on each output against its own input (the N-way fit can leave a few folded
// faces where a map squeezes a limb: doc/results.md); then the three are blended with affine weights, and the
// head of the third is put on the body of the first by a local blend around the nose feature.
#include <crossparam/blending.h>
#include <crossparam/multi_remeshing.h>
#include <crossparam/remeshing_verification.h>
#include <support/shapes.h>

#include <iostream>

using Surface_mesh = crossparam::Surface_mesh;

int main() try {
  namespace shapes = crossparam::shapes;
  shapes::Creature_params params_c = shapes::creature_a_params(); // a third animal: long neck and tail, short legs
  params_c.neck_length = 0.8;
  params_c.neck_elevation_deg = 55;
  params_c.leg_length = 0.55;
  params_c.tail_length = 0.9;
  params_c.tail_bend_deg = 90;
  const std::vector<Surface_mesh> meshes{shapes::creature_a(), shapes::creature_b(), shapes::make_creature(params_c)};
  const crossparam::Feature_correspondence ab = shapes::creature_features(meshes[0], meshes[1]);
  const crossparam::Feature_correspondence ac =
      shapes::creature_features(meshes[0], shapes::creature_a_params(), meshes[2], params_c);
  crossparam::Multi_feature_correspondence features;
  for (std::size_t k = 0; k < ab.size(); ++k) features.push_back({ab[k].source, ab[k].target, ac[k].target});

  constexpr double tolerance = 1.0; // percent of each model's bounding-box diagonal
  const crossparam::Multi_remesher<Surface_mesh> r(meshes, features, crossparam::parameters::tolerance(tolerance));
  std::cout << "one face list of " << r.faces().size() << " faces, " << r.points(0).size() << " vertices\n";
  bool ok = true;
  Surface_mesh out_source;
  r.copy_to(0, out_source);
  for (std::size_t m = 1; m < meshes.size(); ++m) {
    Surface_mesh out;
    r.copy_to(m, out);
    const crossparam::Remeshing_verification v =
        crossparam::verify_compatible_remeshing(meshes[0], meshes[m], out_source, out, tolerance);
    std::cout << "model " << m << ": Hausdorff " << v.hausdorff_target << "%, " << v.flipped_faces << " flipped faces"
              << (v.valid ? "" : " (" + v.message + ")") << "\n";
    ok = ok && v.compatible;
  }
  const auto third = crossparam::blend({&r.points(0), &r.points(1), &r.points(2)}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  // The region: within 0.3 body units of the nose (feature 0), falling off over the next 0.3.
  const std::vector<double> head =
      crossparam::feature_region_weights(r.points(0), r.faces(), {features[0][0]}, 0, 0.3, 0.3);
  const auto pasted = crossparam::local_blend({&r.points(0), &r.points(2)}, crossparam::two_mesh_weights(head));
  std::size_t inside = 0;
  for (double w : head) inside += w > 0.5;
  std::cout << "blend of the three: " << third.size() << " points; local blend: " << inside
            << " vertices follow the third model's head, " << pasted.size() - inside << " the first's body\n";
  return ok ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}
