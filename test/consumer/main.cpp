// SPDX-License-Identifier: GPL-3.0-or-later
#include <crossparam/crossparam.h> // every public header, as installed
#include <iostream>
int main() {
  crossparam::Polygon_soup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  soup.polygons = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  crossparam::Surface_mesh m;
  auto report = crossparam::soup_to_triangle_mesh(soup, m, "tetrahedron");
  const int genus = crossparam::check_triangle_mesh(m, "tetrahedron").genus;
  std::cout << m.number_of_vertices() << " vertices, genus " << report.genus << "\n";
  return m.number_of_vertices() == 4 && report.genus == 0 && genus == 0 ? 0 : 1;
}
