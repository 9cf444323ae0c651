// Math and geometry below the renderer: transforms and their inverses, the
// shape intersection routines, and the BVH checked against brute force on
// thousands of random rays.
#include <gtest/gtest.h>

#include <cmath>

#include "glint/accel/accelerator.h"
#include "glint/geometry/shapes.h"
#include "glint/math/rng.h"
#include "glint/math/transform.h"

namespace glint {
namespace {

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Transform, InverseUndoesTheMap) {
  const Transform t = compose(Transform::translate({1, -2, 3}),
                              compose(Transform::rotate(normalize(Vec3{1, 2, 3}), 37), Transform::scale({2, 0.5, 3})));
  const Vec3 p{0.3, -0.7, 1.9};
  expect_vec(t.inverse_point(t.point(p)), p, 1e-12);
  expect_vec(t.inverse_vector(t.vector(p)), p, 1e-12);
  // Normals stay perpendicular to transformed tangents.
  const Vec3 n{0, 0, 1}, tangent{1, 1, 0};
  EXPECT_NEAR(dot(t.normal(n), t.vector(tangent)), 0.0, 1e-12);
}

TEST(Transform, RotationFollowsTheRightHandRule) {
  expect_vec(Transform::rotate({0, 0, 1}, 90).vector({1, 0, 0}), {0, 1, 0}, 1e-15);
  expect_vec(Transform::rotate({0, 1, 0}, 90).vector({0, 0, 1}), {1, 0, 0}, 1e-15);
}

TEST(Transform, FromAffineInvertsWellConditionedMatricesAtAnyScale) {
  for (double s : {1e-200, 1e-8, 1.0, 1e8, 1e300}) {
    Affine a = Transform::identity_affine();
    a[0][0] = s;
    a[1][1] = 2 * s;
    a[2][2] = 3 * s;
    a[0][3] = 5;
    const auto t = Transform::from_affine(a);
    ASSERT_TRUE(t.has_value()) << s;
    const Vec3 p{1, 2, 3};
    const Vec3 back = t->inverse_point(t->point(p));
    expect_vec(back, p, 1e-9 * std::max(1.0, 5.0 / s));
  }
}

TEST(Transform, SingularMatricesAreRefused) {
  Affine a = Transform::identity_affine();
  a[2][2] = 0;
  EXPECT_FALSE(Transform::from_affine(a).has_value());
  Affine b = {{{1, 2, 3, 0}, {2, 4, 6, 0}, {0, 0, 1, 0}}};  // rows 0 and 1 dependent
  EXPECT_FALSE(Transform::from_affine(b).has_value());
}

TEST(Shapes, SphereFromInsideAndOutside) {
  const Sphere s{{0, 0, 0}, 2};
  EXPECT_NEAR(*intersect_sphere(s, Ray{{0, 0, 10}, {0, 0, -1}}), 8.0, 1e-12);
  EXPECT_NEAR(*intersect_sphere(s, Ray{{0, 0, 0}, {0, 0, -1}}), 2.0, 1e-12);
  EXPECT_FALSE(intersect_sphere(s, Ray{{0, 0, 10}, {0, 0, 1}}).has_value());
  EXPECT_FALSE(intersect_sphere(s, Ray{{0, 2.0001, 10}, {0, 0, -1}}).has_value());
  // Far away rays keep their precision (no cancellation in the discriminant).
  EXPECT_NEAR(*intersect_sphere(s, Ray{{0, 0, 1e7}, {0, 0, -1}}), 1e7 - 2, 1e-6);
}

TEST(Shapes, PlaneAndParallelRays) {
  const Plane p{{0, 1, 0}, {0, 1, 0}};
  EXPECT_NEAR(*intersect_plane(p, Ray{{0, 5, 0}, {0, -2, 0}}), 2.0, 1e-15);
  EXPECT_FALSE(intersect_plane(p, Ray{{0, 5, 0}, {1, 0, 0}}).has_value());
}

TEST(Shapes, TriangleEdgesAndVertices) {
  const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(intersect_triangle(t, Ray{{0.25, 0.25, 1}, {0, 0, -1}}).has_value());
  EXPECT_TRUE(intersect_triangle(t, Ray{{0.5, 0.0, 1}, {0, 0, -1}}).has_value());  // on an edge
  EXPECT_TRUE(intersect_triangle(t, Ray{{0, 0, 1}, {0, 0, -1}}).has_value());      // a vertex
  EXPECT_FALSE(intersect_triangle(t, Ray{{0.6, 0.6, 1}, {0, 0, -1}}).has_value());
  EXPECT_FALSE(intersect_triangle(t, Ray{{0.2, 0.2, 1}, {1, 0, 0}}).has_value());  // parallel
}

TEST(Shapes, BoxFacesFromOutsideAndInside) {
  const Box b{{-1, -1, -1}, {1, 1, 1}};
  auto h = intersect_box(b, Ray{{0, 0, 5}, {0, 0, -1}});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 4.0, 1e-15);
  expect_vec(box_face_normal(h->face), {0, 0, 1}, 0);
  h = intersect_box(b, Ray{{0, 0, 0}, {1, 0, 0}});
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1.0, 1e-15);
  expect_vec(box_face_normal(h->face), {1, 0, 0}, 0);
  // Negative zero in the direction must not lose the box.
  EXPECT_TRUE(intersect_box(b, Ray{{0, 0, 5}, {-0.0, -0.0, -1}}).has_value());
}

Scene random_scene(int count, uint64_t seed) {
  Scene scene;
  Rng rng(seed);
  auto u = [&] { return rng.next_double() * 20 - 10; };
  for (int i = 0; i < count; ++i) {
    switch (i % 4) {
      case 0: add_sphere(scene, Sphere{{u(), u(), u()}, 0.1 + rng.next_double()}); break;
      case 1: {
        const Vec3 c{u(), u(), u()};
        add_triangle(scene,
                     Triangle{c, c + Vec3{rng.next_double() * 2, 0.1, 0}, c + Vec3{0, rng.next_double() * 2, 0.3}});
        break;
      }
      case 2: {
        const Vec3 c{u(), u(), u()};
        add_box(scene, Box{c, c + Vec3{0.2 + rng.next_double(), 0.2 + rng.next_double(), 0.2 + rng.next_double()}}, 0,
                Transform::rotate(normalize(Vec3{1, 1, 0}), 360 * rng.next_double()));
        break;
      }
      case 3:
        add_sphere(scene, Sphere{{0, 0, 0}, 1}, 0,
                   compose(Transform::translate({u(), u(), u()}), Transform::scale({0.3, 1.2, 0.6})));
        break;
    }
  }
  add_plane(scene, Plane{{0, -12, 0}, {0, 1, 0}});
  return scene;
}

TEST(Bvh, MatchesBruteForceOnRandomRays) {
  // 20000 objects also exercise the parallel (multi-threaded) build.
  for (int count : {1, 7, 100, 2000, 20000}) {
    const Scene scene = random_scene(count, 42 + count);
    const auto bvh = build_accelerator(scene);
    const auto brute = build_brute_force(scene);
    Rng rng(7);
    int hits = 0;
    const int rays = count > 5000 ? 500 : 5000;
    for (int i = 0; i < rays; ++i) {
      Ray ray;
      ray.origin = {rng.next_double() * 30 - 15, rng.next_double() * 30 - 15, rng.next_double() * 30 - 15};
      ray.direction = normalize(Vec3{rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5});
      if (i % 3 == 0) ray.t_max = rng.next_double() * 20;
      const auto a = bvh->intersect(ray);
      const auto b = brute->intersect(ray);
      ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i << " count " << count;
      if (a) {
        ++hits;
        EXPECT_EQ(a->object, b->object);
        EXPECT_EQ(a->t, b->t);
      }
      EXPECT_EQ(bvh->occluded(ray), brute->occluded(ray));
    }
    if (count >= 100) {
      EXPECT_GT(hits, rays / 5);
    }
  }
}

}  // namespace
}  // namespace glint
