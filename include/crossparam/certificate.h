// SPDX-License-Identifier: GPL-3.0-or-later
// The bijectivity certificate (Kraevoy & Sheffer 2004, §4): the result of the exact test that the
// piecewise-linear map of a mesh onto the base domain is one-to-one. `Cross_parameterization::certificate()`
// reports it for each input mesh, `Compatible_remesher::certificate()` for the remeshed source.
#ifndef CROSSPARAM_CERTIFICATE_H
#define CROSSPARAM_CERTIFICATE_H

#include <cstddef>
#include <string>

namespace crossparam {

/// Result of the bijectivity certificate of one mesh's map onto the base mesh. Every face's image is tested
/// with the exact orientation predicate in a chart of at most two adjacent base triangles, and one probe point
/// of the base mesh is checked to be covered exactly once: together, the map is one-to-one.
struct Bijectivity_certificate {
  bool valid = false;
  std::size_t faces = 0;          ///< faces checked
  std::size_t not_positive = 0;   ///< faces whose image is flipped or degenerate (exact predicate)
  std::size_t not_in_a_chart = 0; ///< faces whose corners span more than two adjacent base triangles
  std::size_t coverage = 0;       ///< faces covering a probe point of the base mesh (1 when one-to-one)
  std::string message;            ///< empty when valid
};

} // namespace crossparam

#endif // CROSSPARAM_CERTIFICATE_H
