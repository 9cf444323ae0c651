#include "glint/accel/triangle_blocks.h"

namespace glint {

TriangleVertices block_vertices(const Triangle4& b, int lane) {
  return {Vec3f{b.v[0][0][lane], b.v[0][1][lane], b.v[0][2][lane]},
          Vec3f{b.v[1][0][lane], b.v[1][1][lane], b.v[1][2][lane]},
          Vec3f{b.v[2][0][lane], b.v[2][1][lane], b.v[2][2][lane]}};
}

Triangle block_triangle(const Triangle4& b, int lane) {
  return {Vec3(b.v[0][0][lane], b.v[0][1][lane], b.v[0][2][lane]),
          Vec3(b.v[1][0][lane], b.v[1][1][lane], b.v[1][2][lane]),
          Vec3(b.v[2][0][lane], b.v[2][1][lane], b.v[2][2][lane])};
}

}  // namespace glint
