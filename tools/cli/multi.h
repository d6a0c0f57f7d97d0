// SPDX-License-Identifier: GPL-3.0-or-later
// The CLI's commands on many models and on transfers: `remesh` with three or more meshes (one common
// connectivity, paper §2.3), `blend` (affine and local blends of compatible meshes) and `transfer` (a textured
// source's texture coordinates onto the target's shape, and per-vertex data onto the target's vertices).
#ifndef CROSSPARAM_CLI_MULTI_H
#define CROSSPARAM_CLI_MULTI_H

#include "commands.h"
#include "options.h"
#include "outputs.h"

#include <crossparam/attribute_transfer.h>
#include <crossparam/blending.h>
#include <crossparam/morph.h>
#include <crossparam/multi_remeshing.h>
#include <crossparam/textured_obj.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace crossparam {
namespace cli {

/// `remesh M0 M1 M2 ...`: one connectivity for all, compatible_<k>.off per mesh in command-line order, each
/// output checked against its input by the independent verifier, and report.json.
inline int run_multi_remesh(const Options& o) {
  if (o.features.empty()) throw Usage_error("remesh needs --features FILE");
  if (o.output.empty()) throw Usage_error("remesh needs -o DIR");
  Timer tr;
  std::vector<Surface_mesh> meshes;
  std::vector<std::size_t> counts;
  for (const std::string& p : o.positional) {
    meshes.push_back(load(p, o).mesh);
    counts.push_back(meshes.back().number_of_vertices());
  }
  const Multi_feature_correspondence features = read_multi_features(o.features, counts);
  if (o.source_mesh != finest_mesh && o.source_mesh >= meshes.size())
    throw Usage_error("--source-mesh " + std::to_string(o.source_mesh) + ": there are " + std::to_string(meshes.size()) + " meshes");
  const double read_s = tr.seconds();
  using namespace crossparam::parameters;
  const Multi_remesher<Surface_mesh> r(
      meshes, features,
      tolerance(o.tolerance, remeshing_construction(o.construction, progress(progress_printer(o), number_of_threads(o.threads, source_mesh(o.source_mesh,
          apply_path_flips(o.flips, straighten_paths(o.straighten, apply_smoothing(o.smoothing, map_smoothing(o.map_smoothing,
              protrusion_features(o.protrusion_features, extremity_features(o.extremity_features,
                  select_extremity_features(o.select_extremities, CGAL::parameters::number_of_iterations(o.iterations))))))))))))));
  const Multi_remeshing_statistics& S = r.statistics();
  // The independent checks: one face list, and each output against its own input.
  Timer tv;
  std::vector<Surface_mesh> outs(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) r.copy_to(m, outs[m]);
  bool one_face_list = true;
  for (std::size_t m = 1; m < outs.size(); ++m) one_face_list = one_face_list && are_compatible(outs[0], outs[m]);
  std::vector<Remeshing_verification> checks(meshes.size());
  bool all_valid = one_face_list;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (m == S.source) continue;
    checks[m] = verify_compatible_remeshing(meshes[S.source], meshes[m], outs[S.source], outs[m], o.tolerance);
    if (!checks[m].valid) {
      all_valid = false;
      std::cerr << "crossparam: output " << m << " fails its independent verification: " << checks[m].message << "\n";
    }
  }
  const double verify_s = tv.seconds();
  fs::create_directories(o.output);
  for (std::size_t m = 0; m < meshes.size(); ++m)
    write_off(output_path(o, "compatible_" + std::to_string(m) + ".off"), r.points(m), r.faces());
  std::size_t largest = 0;
  for (std::size_t c : counts) largest = std::max(largest, c);
  write_report(o, [&](Json_writer& j) {
    j.member("stage", "remesh_n");
    j.member("meshes", meshes.size()).member("source", S.source).member("features", features.size());
    j.member("tolerance_percent", o.tolerance);
    j.member("output_vertices", S.output_vertices).member("output_faces", S.output_faces);
    j.member("largest_input_vertices", largest).member("retriangulated_source_faces", S.retriangulated_faces);
    j.member("flipped_caps", S.flipped_caps).member("merged_needles", S.merged_needles);
    j.member("one_face_list", one_face_list).member("valid", all_valid).member("converged", S.converged);
    j.key("per_mesh").begin_array();
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      j.begin_object().member("input", o.positional[m]).member("input_vertices", counts[m]);
      j.member("bad_faces_before_repair", S.bad_faces_before_repair[m]).member("bad_faces_after_repair", S.bad_faces_after_repair[m]);
      j.member("repair_moves", S.repair_moves[m]);
      j.member("repair_disks", S.repair_disks[m]);
      if (m != S.source) {
        j.member("hausdorff_percent", checks[m].hausdorff_target).member("flipped_faces", checks[m].flipped_faces);
        j.member("flipped_at_target_folds", checks[m].flipped_at_target_folds);
        j.member("new_self_intersections", checks[m].new_self_intersections);
        j.member("valid", checks[m].valid).member("fitted_vertices", S.fitted_vertices[m]).member("max_chord_percent", S.max_chord_error[m]);
        j.member("seconds_map", S.seconds_map[m]).member("seconds_fit", S.seconds_fit[m]);
      } else {
        j.member("source", true);
      }
      j.end_object();
    }
    j.end_array();
    j.key("seconds").begin_object().member("read", read_s).member("total", S.seconds_total).member("output_repair", S.seconds_repair).member("verification", verify_s).end_object();
  });
  if (!o.quiet) {
    std::cout << "remesh: " << meshes.size() << " meshes, one face list of " << S.output_faces << " faces, "
              << S.output_vertices << " vertices (largest input " << largest << "), source mesh " << S.source << "\n";
    for (std::size_t m = 0; m < meshes.size(); ++m)
      if (m != S.source)
        std::cout << "  mesh " << m << ": Hausdorff " << format_number(checks[m].hausdorff_target) << "% (tolerance "
                  << format_number(o.tolerance) << "%), " << checks[m].flipped_faces << " flipped faces ("
                  << checks[m].flipped_at_target_folds << " at the target's own folds)"
                  << ", " << checks[m].new_self_intersections << " new self-intersecting face pairs"
                  << (checks[m].valid ? "" : " (NOT valid)") << "\n";
    std::cout << "  " << format_number(S.seconds_total) << " s; wrote " << o.output << "/\n";
  }
  return all_valid ? 0 : failed_verification(o, "see the outputs above");
}

/// A list of numbers "a,b,c", or a usage error naming `option`.
inline std::vector<double> parse_numbers(const std::string& option, const std::string& v) {
  std::vector<double> out;
  std::stringstream s(v);
  std::string tok;
  while (std::getline(s, tok, ',')) {
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);
    if (tok.empty() || *end != '\0' || !std::isfinite(x)) throw Usage_error(option + " needs numbers separated by commas");
    out.push_back(x);
  }
  if (out.empty()) throw Usage_error(option + " needs numbers separated by commas");
  return out;
}

/// Per-vertex rows of numbers from a text file ('#' comments, blank lines ignored).
inline std::vector<std::vector<double>> read_rows(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Input_error(path + ": cannot open the file");
  std::vector<std::vector<double>> rows;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    line = line.substr(0, line.find('#'));
    std::istringstream s(line);
    std::vector<double> row;
    std::string tok;
    while (s >> tok) {
      char* end = nullptr;
      const double x = std::strtod(tok.c_str(), &end);
      if (*end != '\0' || !std::isfinite(x)) throw Input_error(path + ": line " + std::to_string(n) + ": '" + tok + "' is not a number");
      row.push_back(x);
    }
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

/// Frames of the textured morph strip, and the strip picture's size per frame.
constexpr unsigned textured_strip_frames = 5;
constexpr int textured_strip_frame_width = 300, textured_strip_height = 320;
/// Distance between neighbouring meshes in a strip or a triangle of blends, in mesh widths (a small gap).
constexpr double picture_pitch = 1.15;

/// The right and up directions of the pictures (as render_png frames them), for laying meshes out side by side.
inline std::array<double, 3> picture_right(const Options& o) { return unit3(cross3(o.render.up, o.render.view_direction)); }

/// Extent of a point list along a unit direction.
inline double extent_along(const std::vector<std::array<double, 3>>& pts, const std::array<double, 3>& d) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const auto& p : pts) {
    const double x = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
    lo = std::min(lo, x), hi = std::max(hi, x);
  }
  return hi - lo;
}

/// Appends `pts` shifted by `shift`, with `tris`, to a picture.
inline void append_shifted(Render_mesh& picture, const std::vector<std::array<double, 3>>& pts,
                           const std::vector<std::array<std::size_t, 3>>& tris, const std::array<double, 3>& shift) {
  const std::size_t base = picture.points.size();
  for (const auto& p : pts) picture.points.push_back({p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]});
  for (const auto& f : tris) picture.triangles.push_back({f[0] + base, f[1] + base, f[2] + base});
}

/// Rows of the triangle of blends: the corners are the three inputs, the blend at row i, column j (j <= i) has
/// weights (1 - i/R, (i - j)/R, j/R) with R = rows - 1.
constexpr unsigned blend_triangle_rows = 5;
constexpr int blend_triangle_cell = 220;

/// blend_triangle.png: the three-sided blend of the paper's Fig. 1 (right), the inputs at the corners.
inline void write_blend_triangle(const Options& o, const std::vector<const std::vector<std::array<double, 3>>*>& pts,
                                 const std::vector<std::array<std::size_t, 3>>& tris) {
  const std::array<double, 3> right = picture_right(o), up = unit3(o.render.up);
  double width = 0, height = 0;
  for (const auto* p : pts) width = std::max(width, extent_along(*p, right)), height = std::max(height, extent_along(*p, up));
  Render_mesh picture;
  const double R = blend_triangle_rows - 1;
  for (unsigned i = 0; i < blend_triangle_rows; ++i)
    for (unsigned j = 0; j <= i; ++j) {
      const std::vector<double> w{1 - i / R, (i - j) / R, j / R};
      const double x = picture_pitch * width * (double(j) - 0.5 * i), y = -picture_pitch * height * double(i);
      append_shifted(picture, blend(pts, w), tris,
                     {x * right[0] + y * up[0], x * right[1] + y * up[1], x * right[2] + y * up[2]});
    }
  Render_options ro = o.render;
  ro.width = ro.height = blend_triangle_cell * int(blend_triangle_rows);
  render_png(picture, output_path(o, "blend_triangle.png"), ro);
}

/// `blend M0 M1 ... -o DIR` with `--weights`, `--weight-file` or (two meshes) `--region`: blend.off.
inline int run_blend(const Options& o) {
  if (o.positional.size() < 2) throw Usage_error("blend needs at least two compatible meshes");
  if (o.output.empty()) throw Usage_error("blend needs -o DIR");
  const int modes = !o.weights.empty() + !o.weight_file.empty() + !o.region.empty();
  if (modes != 1) throw Usage_error("blend needs one of --weights, --weight-file and --region");
  std::vector<Polygon_soup> soups;
  for (const std::string& p : o.positional) {
    soups.push_back(read_polygon_soup(p));
    check_compatible(soups[0], soups.back(), o.positional[0], p);
  }
  std::vector<const std::vector<std::array<double, 3>>*> pts;
  for (const auto& s : soups) pts.push_back(&s.points);
  std::vector<std::array<std::size_t, 3>> tris;
  for (const auto& p : soups[0].polygons) {
    if (p.size() != 3) throw Input_error(o.positional[0] + ": the blend needs triangles");
    tris.push_back({p[0], p[1], p[2]});
  }
  std::vector<std::array<double, 3>> out;
  std::vector<double> region;
  if (!o.weights.empty()) {
    out = blend(pts, parse_numbers("--weights", o.weights));
  } else if (!o.weight_file.empty()) {
    out = local_blend(pts, read_rows(o.weight_file));
  } else {
    if (soups.size() != 2) throw Usage_error("--region blends two meshes: the second inside the region, the first outside");
    if (o.features.empty()) throw Usage_error("--region needs --features FILE (the first column: vertices of the compatible meshes)");
    const std::vector<double> r = parse_numbers("--region", o.region);
    if (r.size() < 2 || r.size() > 3 || r[0] < 0 || r[0] != std::floor(r[0]))
      throw Usage_error("--region needs FEATURE,RADIUS[,FALLOFF] (a feature index, then lengths in units of the square root of the area)");
    std::vector<std::size_t> counts(1, soups[0].points.size());
    std::vector<std::size_t> feature_vertices;
    for (const auto& row : read_rows(o.features)) {
      if (row.empty() || row[0] < 0 || row[0] != std::floor(row[0]) || row[0] >= double(counts[0]))
        throw Feature_error(o.features + ": a first column that is not a vertex of the compatible meshes");
      feature_vertices.push_back(std::size_t(row[0]));
    }
    double area = 0;
    for (const auto& t : tris) {
      const auto& a = soups[0].points[t[0]];
      const auto& b = soups[0].points[t[1]];
      const auto& c = soups[0].points[t[2]];
      const Kernel::Vector_3 u(b[0] - a[0], b[1] - a[1], b[2] - a[2]), v(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
      area += 0.5 * std::sqrt(CGAL::cross_product(u, v).squared_length());
    }
    const double unit = std::sqrt(area);
    region = feature_region_weights(soups[0].points, tris, feature_vertices, std::size_t(r[0]), r[1] * unit,
                                    (r.size() > 2 ? r[2] : 0.5 * r[1]) * unit);
    out = local_blend(pts, two_mesh_weights(region));
  }
  fs::create_directories(o.output);
  write_off(output_path(o, "blend.off"), out, tris);
  if (o.png) {
    Render_mesh picture{out, tris, {}, {}};
    if (!region.empty())
      for (double w : region) picture.vertex_colors.push_back({static_cast<unsigned char>(200 - 120 * w), 200, static_cast<unsigned char>(120 + 80 * w)});
    render_png(picture, output_path(o, "blend.png"), o.render);
    if (soups.size() == 3) write_blend_triangle(o, pts, tris);
  }
  if (!o.quiet) std::cout << "blend: " << soups.size() << " meshes of " << out.size() << " vertices; wrote " << o.output << "/blend.off\n";
  return 0;
}

/// The pictures of `transfer`: the source with its own texture, the target's shape with the source's texture,
/// and a strip of the textured morph from one to the other.
inline void write_transfer_pictures(const Options& o, const Textured_mesh& source, const std::vector<std::array<double, 3>>& source_points,
                                    const std::vector<std::array<double, 3>>& target_points,
                                    const std::vector<std::array<std::size_t, 3>>& faces, const std::vector<Corner_uvs>& uvs,
                                    const std::string& texture) {
  Render_mesh s;
  s.points = source.points;
  s.triangles = source.uv.face_vertices;
  Render_texture st{texture, {}};
  for (const auto& t : source.uv.face_uvs) st.corner_uvs.push_back({source.uv.uvs[t[0]], source.uv.uvs[t[1]], source.uv.uvs[t[2]]});
  render_png(s, output_path(o, "source_textured.png"), o.render, &st);
  Render_texture tt{texture, uvs};
  Render_mesh t;
  t.points = target_points;
  t.triangles = faces;
  render_png(t, output_path(o, "target_textured.png"), o.render, &tt);
  Render_mesh strip;
  Render_texture strip_texture{texture, {}};
  const std::array<double, 3> right = picture_right(o);
  const double width = std::max(extent_along(source_points, right), extent_along(target_points, right));
  for (unsigned k = 0; k < textured_strip_frames; ++k) {
    const double t = double(k) / double(textured_strip_frames - 1), shift = picture_pitch * width * k;
    append_shifted(strip, morph(source_points, target_points, t), faces, {shift * right[0], shift * right[1], shift * right[2]});
    strip_texture.corner_uvs.insert(strip_texture.corner_uvs.end(), uvs.begin(), uvs.end());
  }
  Render_options so = o.render;
  so.height = textured_strip_height;
  so.width = textured_strip_frame_width * int(textured_strip_frames);
  render_png(strip, output_path(o, "textured_morph_strip.png"), so, &strip_texture);
}

/// `transfer SOURCE.obj TARGET --features FILE -o DIR`: the source's texture coordinates onto the target-shaped
/// compatible mesh (target_textured.obj, .mtl and the image), checked corner by corner; with `--attributes`,
/// per-vertex data of the source onto the target's own vertices (target_attributes.txt).
inline int run_transfer(const Options& o) {
  if (o.positional.size() != 2) throw Usage_error("transfer needs SOURCE.obj and TARGET");
  if (o.features.empty()) throw Usage_error("transfer needs --features FILE");
  if (o.output.empty()) throw Usage_error("transfer needs -o DIR");
  Timer tr;
  const Textured_mesh textured = read_textured_obj(o.positional[0]);
  Polygon_soup soup;
  soup.points = textured.points;
  for (const auto& f : textured.uv.face_vertices) soup.polygons.push_back({f[0], f[1], f[2]});
  Surface_mesh source;
  soup_to_triangle_mesh(soup, source, o.positional[0]);
  if (source.number_of_faces() != textured.uv.face_vertices.size())
    throw Input_error(o.positional[0] + ": the mesh's faces changed when read (texture coordinates would not match)");
  Surface_mesh target = load(o.positional[1], o).mesh;
  const Feature_correspondence f = read_feature_pairs(o.features, source.number_of_vertices(), target.number_of_vertices());
  const std::string texture = !o.texture.empty() ? o.texture : textured.texture;
  if (texture.empty()) throw Usage_error(o.positional[0] + " names no texture image: give --texture IMG");
  if (!fs::exists(texture)) throw Input_error(texture + ": the texture image does not exist");
  const Surface_mesh source0 = source, target0 = target;
  const double read_s = tr.seconds();
  Map cp = cross_parameterize(o, source, target, f);
  const Remesher r = remesh(o, cp);
  const std::vector<Corner_uvs> uvs = transfer_corner_uvs(r.source_face_locations(), textured.uv);
  // The check: each face's corners, located geometrically in the source face holding them, interpolate that
  // face's texture coordinates to the values written.
  double worst = 0;
  for (std::size_t g = 0; g < uvs.size(); ++g) {
    const std::size_t face = r.source_face_locations()[g].face;
    const auto& fv = textured.uv.face_vertices[face];
    const auto& ft = textured.uv.face_uvs[face];
    auto P = [&](std::size_t i) { const auto& p = textured.points[i]; return Point_3(p[0], p[1], p[2]); };
    const Point_3 a = P(fv[0]), b = P(fv[1]), c = P(fv[2]);
    for (int k = 0; k < 3; ++k) {
      const auto& q = r.source_points()[r.faces()[g][std::size_t(k)]];
      const auto v0 = b - a, v1 = c - a, v2 = Point_3(q[0], q[1], q[2]) - a;
      const double d00 = v0 * v0, d01 = v0 * v1, d11 = v1 * v1, d20 = v2 * v0, d21 = v2 * v1, den = d00 * d11 - d01 * d01;
      const double bv = (d11 * d20 - d01 * d21) / den, bw = (d00 * d21 - d01 * d20) / den;
      const double bc[3] = {1 - bv - bw, bv, bw};
      for (int d = 0; d < 2; ++d) {
        double e = 0;
        for (int i = 0; i < 3; ++i) e += bc[i] * textured.uv.uvs[ft[std::size_t(i)]][std::size_t(d)];
        worst = std::max(worst, std::abs(e - uvs[g][std::size_t(k)][std::size_t(d)]));
      }
    }
  }
  Surface_mesh out_source, out_target;
  r.copy_to(Mesh_side::source, out_source);
  r.copy_to(Mesh_side::target, out_target);
  const Remeshing_verification check = verify_compatible_remeshing(source0, target0, out_source, out_target, o.tolerance);
  if (!check.valid) std::cerr << "crossparam: warning: the remeshing misses its tolerance: " << check.message << "\n";
  fs::create_directories(o.output);
  const std::string image = fs::path(texture).filename().string();
  fs::copy_file(texture, output_path(o, image), fs::copy_options::overwrite_existing);
  write_textured_obj(output_path(o, "target_textured.obj"), r.target_points(), r.faces(), uvs, image);
  write_textured_obj(output_path(o, "source_textured.obj"), r.source_points(), r.faces(), uvs, image);
  std::size_t attribute_columns = 0;
  if (!o.attributes.empty()) {
    const Vertex_data data = read_rows(o.attributes);
    const Vertex_data on_target = transfer_vertex_data(cp, Mesh_side::source, data);
    attribute_columns = data.empty() ? 0 : data[0].size();
    write_file_atomically(output_path(o, "target_attributes.txt"), [&](std::ostream& os) {
      os << "# one row per vertex of " << fs::path(o.positional[1]).filename().string() << ", interpolated from "
         << fs::path(o.attributes).filename().string() << " through the map\n";
      for (const auto& row : on_target) {
        for (std::size_t k = 0; k < row.size(); ++k) os << (k ? " " : "") << row[k];
        os << "\n";
      }
    });
  }
  if (o.png) write_transfer_pictures(o, textured, r.source_points(), r.target_points(), r.faces(), uvs, output_path(o, image));
  const Remeshing_statistics& S = r.statistics();
  write_report(o, [&](Json_writer& j) {
    j.member("stage", "transfer");
    j.member("source_vertices", S.source_vertices).member("target_vertices", S.target_vertices);
    j.member("output_vertices", S.output_vertices).member("output_faces", S.output_faces);
    j.member("texture", image).member("texture_coordinates_max_deviation", worst);
    j.member("attribute_columns", attribute_columns);
    j.key("verification").begin_object().member("valid", check.valid).member("hausdorff_percent", check.hausdorff_target);
    j.member("flipped_faces", check.flipped_faces).member("flipped_at_target_folds", check.flipped_at_target_folds);
    j.member("new_self_intersections", check.new_self_intersections).end_object();
    j.key("seconds").begin_object().member("read", read_s).member("map", cp.statistics().seconds_total);
    j.member("remesh", S.seconds_total).end_object();
  });
  if (!o.quiet)
    std::cout << "transfer: " << S.output_faces << " faces carry the source's texture coordinates (largest deviation "
              << "from their source face's interpolation " << format_number(worst) << "); Hausdorff to the target "
              << format_number(check.hausdorff_target) << "%, " << check.flipped_faces << " flipped faces ("
              << check.flipped_at_target_folds << " at the target's own folds); wrote "
              << o.output << "/target_textured.obj\n";
  return 0;
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_MULTI_H
