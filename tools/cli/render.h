// SPDX-License-Identifier: GPL-3.0-or-later
// Pictures for the CLI's --png: a coloured triangle mesh rendered to PNG with POV-Ray (Debian package
// `povray`), headless, through std::system. Part of the command-line tool, not of the library.
#ifndef CROSSPARAM_CLI_RENDER_H
#define CROSSPARAM_CLI_RENDER_H

#include <crossparam/errors.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace crossparam {
namespace cli {

/// What to draw and how. Colors are per vertex (interpolated) if `vertex_colors` is non-empty, else per face.
struct Render_mesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  std::vector<std::array<unsigned char, 3>> face_colors;
  std::vector<std::array<unsigned char, 3>> vertex_colors;
};

/// A texture instead of colours: a PNG image and, per triangle of the mesh, its corners' (u, v) in it.
struct Render_texture {
  std::string png;
  std::vector<std::array<std::array<double, 2>, 3>> corner_uvs;
};

struct Render_options {
  int width = 640;
  int height = 480;
  /// Direction from the object's centre to the camera (any length).
  std::array<double, 3> view_direction{0.6, 0.45, 1.0};
  std::array<double, 3> up{0, 1, 0};
  /// Moves the camera closer (> 1) or farther (< 1) at the same framing: less or more perspective.
  double zoom = 1.0;
  /// If set, the view is framed on this bounding box instead of the mesh's (keeps a morph sequence steady).
  bool fixed_frame = false;
  std::array<double, 3> frame_min{0, 0, 0}, frame_max{0, 0, 0};
  std::array<unsigned char, 3> background{255, 255, 255};
};

/// True if the `povray` executable can be found on PATH.
inline bool povray_available() { return std::system("command -v povray >/dev/null 2>&1") == 0; }

inline std::array<double, 3> sub3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline std::array<double, 3> cross3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline std::array<double, 3> unit3(std::array<double, 3> a) {
  double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (n > 0)
    for (double& x : a) x /= n;
  return a;
}

/// The camera's horizontal opening angle (degrees) that frames the points `for_each_point` visits (model
/// coordinates as the camera sees them: centred, unit bounding sphere) from `dist` along `dirn`, with a 5 %
/// margin on the tighter side: tall models fit in height as wide ones do in width.
template <class ForEachPoint>
double view_angle(const Render_options& opt, const std::array<double, 3>& dirn, double dist, ForEachPoint for_each_point) {
  // Camera frame: up projected off the view direction, right = up x view.
  std::array<double, 3> up = opt.up;
  const double d = up[0] * dirn[0] + up[1] * dirn[1] + up[2] * dirn[2];
  for (int i = 0; i < 3; ++i) up[i] -= d * dirn[i];
  up = unit3(up);
  const std::array<double, 3> right = unit3(cross3(up, dirn));
  const double aspect = double(opt.width) / opt.height;
  double half = 0; // tangent of the half angle, horizontally
  for_each_point([&](const std::array<double, 3>& p) {
    const double depth = dist - (p[0] * dirn[0] + p[1] * dirn[1] + p[2] * dirn[2]);
    if (!(depth > 0)) return;
    const double x = std::abs(p[0] * right[0] + p[1] * right[1] + p[2] * right[2]) / depth;
    const double y = std::abs(p[0] * up[0] + p[1] * up[1] + p[2] * up[2]) / depth;
    half = std::max({half, x, y * aspect});
  });
  if (!(half > 0)) return 38;
  return 2 * std::atan(1.05 * half) * 180 / 3.14159265358979323846;
}

/// Renders `mesh` to the PNG file `png_path` with POV-Ray. Throws Error with a clear message if POV-Ray is
/// not installed or fails. The PNG is written through a temporary file and renamed.
inline void render_png(const Render_mesh& mesh, const std::string& png_path, const Render_options& opt = {},
                       const Render_texture* texture = nullptr) {
  namespace fs = std::filesystem;
  if (!povray_available())
    throw Error("cannot render " + png_path + ": POV-Ray is not installed (apt-get install povray)");
  if (mesh.points.empty() || mesh.triangles.empty()) throw Error("cannot render " + png_path + ": empty mesh");
  std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  if (opt.fixed_frame) {
    lo = opt.frame_min;
    hi = opt.frame_max;
  } else {
    for (const auto& p : mesh.points)
      for (int i = 0; i < 3; ++i) {
        lo[i] = std::min(lo[i], p[i]);
        hi[i] = std::max(hi[i], p[i]);
      }
  }
  std::array<double, 3> c{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  double radius = 0.5 * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
  // Normalise to a unit sphere so POV-Ray never sees extreme magnitudes.
  auto P = [&](const std::array<double, 3>& p) {
    return std::array<double, 3>{(p[0] - c[0]) / radius, (p[1] - c[1]) / radius, (p[2] - c[2]) / radius};
  };
  // Smooth vertex normals (area weighted).
  std::vector<std::array<double, 3>> normal(mesh.points.size(), {0, 0, 0});
  for (const auto& t : mesh.triangles) {
    auto n = cross3(sub3(P(mesh.points[t[1]]), P(mesh.points[t[0]])),
                              sub3(P(mesh.points[t[2]]), P(mesh.points[t[0]])));
    for (std::size_t k : t)
      for (int i = 0; i < 3; ++i) normal[k][i] += n[i];
  }
  const fs::path png(png_path);
  const fs::path dir = png.parent_path().empty() ? fs::path(".") : png.parent_path();
  const std::string stem = ".crossparam-render-" + std::to_string(std::rand());
  const fs::path pov = dir / (stem + ".pov"), tmp_png = dir / (stem + ".png");
  {
    std::ofstream os(pov);
    if (!os) throw Error("cannot render " + png_path + ": cannot write into " + dir.string());
    os.precision(9);
    auto v3 = [&](const std::array<double, 3>& p) {
      // POV-Ray is left-handed: mirror z.
      os << "<" << p[0] << "," << p[1] << "," << -p[2] << ">";
    };
    auto dirn = unit3(opt.view_direction);
    double dist = 3.2 / opt.zoom;
    std::array<double, 3> cam{dirn[0] * dist, dirn[1] * dist, dirn[2] * dist};
    os << "#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n";
    os << "background { rgb <" << opt.background[0] / 255.0 << "," << opt.background[1] / 255.0 << ","
       << opt.background[2] / 255.0 << "> }\n";
    os << "camera { perspective location ";
    v3(cam);
    os << " sky ";
    v3(opt.up);
    os << " look_at <0,0,0> angle " << view_angle(opt, dirn, dist, [&](auto&& visit) {
      if (opt.fixed_frame) {
        for (int k = 0; k < 8; ++k) visit(P({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]}));
      } else {
        for (const auto& p : mesh.points) visit(P(p));
      }
    }) << " right x*" << double(opt.width) / opt.height << " }\n";
    auto light = [&](std::array<double, 3> d, double s) {
      d = unit3(d);
      os << "light_source { ";
      v3({d[0] * 10, d[1] * 10, d[2] * 10});
      os << " color rgb <" << s << "," << s << "," << s << "> }\n";
    };
    auto side = unit3(cross3(opt.up, dirn));
    light({dirn[0] + side[0] * 0.6 + opt.up[0] * 0.8, dirn[1] + side[1] * 0.6 + opt.up[1] * 0.8,
           dirn[2] + side[2] * 0.6 + opt.up[2] * 0.8},
          0.85);
    light({dirn[0] - side[0], dirn[1] - side[1], dirn[2] - side[2]}, 0.35);
    os << "mesh2 {\n vertex_vectors { " << mesh.points.size();
    for (const auto& p : mesh.points) {
      os << ",\n";
      v3(P(p));
    }
    os << " }\n normal_vectors { " << normal.size();
    for (const auto& n : normal) {
      os << ",\n";
      v3(unit3(n));
    }
    const bool textured = texture && texture->corner_uvs.size() == mesh.triangles.size();
    if (textured) {
      os << " }\n uv_vectors { " << 3 * texture->corner_uvs.size();
      for (const auto& corners : texture->corner_uvs)
        for (const auto& t : corners) os << ",\n<" << t[0] << "," << t[1] << ">";
    }
    const bool per_vertex = !mesh.vertex_colors.empty();
    const auto& colors = per_vertex ? mesh.vertex_colors : mesh.face_colors;
    if (colors.empty()) {
      os << " }\n";
    } else {
      os << " }\n texture_list { " << colors.size();
      for (const auto& col : colors)
        os << ",\n texture { pigment { rgb <" << std::pow(col[0] / 255.0, 2.2) << "," << std::pow(col[1] / 255.0, 2.2)
           << "," << std::pow(col[2] / 255.0, 2.2) << "> } finish { ambient 0.25 diffuse 0.75 specular 0.15 } }";
      os << " }\n";
    }
    os << " face_indices { " << mesh.triangles.size();
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      os << ",\n<" << t[0] << "," << t[1] << "," << t[2] << ">";
      if (per_vertex) os << "," << t[0] << "," << t[1] << "," << t[2];
      else if (!colors.empty()) os << "," << f;
    }
    os << " }\n";
    if (textured) {
      os << " uv_indices { " << mesh.triangles.size();
      for (std::size_t f = 0; f < mesh.triangles.size(); ++f) os << ",\n<" << 3 * f << "," << 3 * f + 1 << "," << 3 * f + 2 << ">";
      os << " }\n texture { uv_mapping pigment { image_map { png \"" << fs::absolute(texture->png).string()
         << "\" interpolate 2 } } finish { ambient 0.25 diffuse 0.75 specular 0.1 } }\n";
    } else if (colors.empty()) {
      os << " texture { pigment { rgb <0.8,0.8,0.8> } finish { ambient 0.25 diffuse 0.75 } }\n";
    }
    os << "}\n";
  }
  const std::string cmd = "povray -D +A0.3 +W" + std::to_string(opt.width) + " +H" + std::to_string(opt.height) +
                          " +I\"" + pov.string() + "\" +O\"" + tmp_png.string() + "\" >/dev/null 2>&1";
  int rc = std::system(cmd.c_str());
  std::error_code ec;
  fs::remove(pov, ec);
  if (rc != 0 || !fs::exists(tmp_png)) {
    fs::remove(tmp_png, ec);
    throw Error("cannot render " + png_path + ": POV-Ray failed (exit code " + std::to_string(rc) + ")");
  }
  fs::rename(tmp_png, png, ec);
  if (ec) throw Error("cannot render " + png_path + ": " + ec.message());
}

} // namespace cli
} // namespace crossparam

#endif // CROSSPARAM_CLI_RENDER_H
