// core/face_geometry.h: a face's vector area, the skew-quad plane of the paper (§2), convexity
// and corner lookup, on faces drawn in code.
#include <gtest/gtest.h>

#include "core/face_geometry.h"

namespace dynpm {
namespace {

TEST(FaceGeometry, DoubledVectorAreaOfATriangleAndAQuad) {
  const Vec3 triangle[3] = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  EXPECT_DOUBLE_EQ(doubled_vector_area(triangle, 3).z, 2.0);  // area 1
  const Vec3 square[4] = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}};
  EXPECT_DOUBLE_EQ(doubled_vector_area(square, 4).z, 12.0);  // area 6: diagonals crossed
}

TEST(FaceGeometry, PlaneOfAPlanarQuadIsItsOwn) {
  const Vec3 square[4] = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};  // z = 1
  const Plane plane = quad_plane(square);
  EXPECT_DOUBLE_EQ(plane.normal.z, 1.0);
  EXPECT_DOUBLE_EQ(plane.offset, -1.0);
}

TEST(FaceGeometry, PlaneOfASkewQuadPassesThroughItsCentroid) {
  // Two opposite corners lifted: the corner normals tilt symmetrically, their mean is +z and
  // the plane passes through the centroid at z = 0.5 (paper §2).
  const Vec3 skew[4] = {{0, 0, 0}, {1, 0, 1}, {1, 1, 0}, {0, 1, 1}};
  const Plane plane = quad_plane(skew);
  EXPECT_NEAR(plane.normal.x, 0, 1e-15);
  EXPECT_NEAR(plane.normal.y, 0, 1e-15);
  EXPECT_DOUBLE_EQ(plane.normal.z, 1.0);
  EXPECT_DOUBLE_EQ(plane.offset, -0.5);
  EXPECT_DOUBLE_EQ(face_plane(skew, 4).offset, plane.offset);
}

TEST(FaceGeometry, ConvexQuadsAndOthers) {
  const Vec3 up{0, 0, 1};
  const Vec3 square[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_TRUE(quad_is_convex(square, up));
  const Vec3 dart[4] = {{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}};  // reflex at corner 2
  EXPECT_FALSE(quad_is_convex(dart, up));
  const Vec3 bowtie[4] = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};  // self-intersecting
  EXPECT_FALSE(quad_is_convex(bowtie, up));
}

TEST(FaceGeometry, CornerOf) {
  Face quad;
  quad.v = {7, 3, 9, 4};
  EXPECT_EQ(corner_of(quad, 9), 2);
  EXPECT_EQ(corner_of(quad, 5), -1);
  Face triangle;
  triangle.v = {1, 2, 3, kNoVertex};
  EXPECT_EQ(corner_of(triangle, 3), 2);
  EXPECT_EQ(corner_of(triangle, 0), -1);
}

}  // namespace
}  // namespace dynpm
