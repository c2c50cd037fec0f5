#pragma once
// Partial derivatives of a height field z(x, y) in world units, the basis of Slope, Aspect, Curvature and
// Normals.
//
// First derivatives: central differences (z[i+1] - z[i-1]) / (2 dx) inside, second-order one-sided
// differences (-3 z0 + 4 z1 - z2) / (2 dx) on the border samples (exact for planes and parabolas, so border
// samples are as good as interior ones). Second derivatives: the three-point stencil, taken at the nearest
// interior sample on the border. The mixed derivative is the y-difference of the x-differences.
#include "graph/heightfield.h"

namespace orogen {

struct SurfaceDerivatives {
  double p = 0.0;  // dz/dx
  double q = 0.0;  // dz/dy
  double r = 0.0;  // d2z/dx2, 1/m
  double s = 0.0;  // d2z/dxdy, 1/m
  double t = 0.0;  // d2z/dy2, 1/m
};

// Gradient (dz/dx, dz/dy) at sample (i, j); dimensionless (metres per metre).
void gradient_at(const Heightfield& z, int i, int j, double& p, double& q);

// All first and second derivatives at sample (i, j).
SurfaceDerivatives derivatives_at(const Heightfield& z, int i, int j);

}  // namespace orogen
