// SPDX-License-Identifier: GPL-3.0-or-later
// Example 03: compatible remeshing (paper §5) and its independent verification.
//
//   example_03_compatible_remeshing        two generated creatures, tolerance 1 %
//
// Remeshes the source so that one face list gives two meshes: one with the source's shape (exactly on the
// source), one with the target's (within the tolerance of the target). verify_compatible_remeshing then checks
// the outputs against the inputs without trusting the remesher: the same face list, CGAL's two-sided Hausdorff
// distance to the target, the distance of the source-shaped mesh to the source, no face flipped.
#include <crossparam/compatible_remeshing.h>
#include <crossparam/remeshing_verification.h>
#include <support/shapes.h>

#include <iostream>

using Surface_mesh = crossparam::Surface_mesh;

int main() try {
  Surface_mesh source = crossparam::shapes::creature_a(), target = crossparam::shapes::creature_b();
  const crossparam::Feature_correspondence features = crossparam::shapes::creature_features(source, target);
  const Surface_mesh source_input = source, target_input = target; // the map refines its meshes in place
  const double tolerance = 1.0; // percent of the target's bounding-box diagonal

  crossparam::Cross_parameterization<Surface_mesh, Surface_mesh> map(source, target, features);
  crossparam::Compatible_remesher<Surface_mesh, Surface_mesh> remesher(map, crossparam::parameters::tolerance(tolerance));
  const crossparam::Remeshing_statistics& s = remesher.statistics();
  std::cout << "remeshed: " << s.source_vertices << " source vertices -> " << s.output_vertices << " vertices, "
            << s.output_faces << " faces (" << s.refinement_splits << " refinement splits, " << s.pseudo_flips
            << " pseudo flips); max error " << s.max_error << "%, L2 " << s.l2_error << "%, " << s.seconds_total
            << " s\n";

  // The two outputs, any MutableFaceGraph: the same vertex order and the same face list.
  Surface_mesh source_shaped, target_shaped;
  remesher.copy_to(crossparam::Mesh_side::source, source_shaped);
  remesher.copy_to(crossparam::Mesh_side::target, target_shaped);

  // The independent check, against the inputs as they were before the map refined them.
  const crossparam::Remeshing_verification v =
      crossparam::verify_compatible_remeshing(source_input, target_input, source_shaped, target_shaped, tolerance);
  std::cout << "verified: " << (v.valid ? "yes" : v.message) << "; compatible " << (v.compatible ? "yes" : "no")
            << ", Hausdorff to the target " << v.hausdorff_target << "% (tolerance " << tolerance
            << "%), source-shaped mesh off the source " << v.hausdorff_source << "%, " << v.flipped_faces
            << " flipped faces, normal deviation " << v.normal_deviation_mean << " degrees on average\n";
  return v.valid ? 0 : 1;
} catch (const crossparam::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 1;
}
