#include "libs/render/scene.h"

#include <Eigen/Geometry>

namespace sylva::render {

void Bounds::extend(const Vec3& p) {
  min = min.cwiseMin(p);
  max = max.cwiseMax(p);
}

void Bounds::extend(const Bounds& b) {
  if (b.empty()) return;
  extend(b.min);
  extend(b.max);
}

Bounds Bounds::transformed(const Mat4& m) const {
  Bounds out;
  if (empty()) return out;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? max.x() : min.x(), (i & 2) ? max.y() : min.y(), (i & 4) ? max.z() : min.z());
    out.extend((m * corner.homogeneous()).hnormalized());
  }
  return out;
}

Bounds Primitive::bounds() const {
  Bounds b;
  for (const Vec3& p : positions) b.extend(p);
  return b;
}

std::size_t Primitive::element_count() const {
  switch (topology) {
    case Topology::kTriangles:
      return indices.size() / 3;
    case Topology::kLines:
      return indices.size() / 2;
    case Topology::kPoints:
      return indices.size();
  }
  return 0;
}

Bounds Scene::bounds() const {
  Bounds out;
  for (const Mesh& mesh : meshes) {
    if (mesh.instances.empty()) continue;
    Bounds local;
    for (const Primitive& p : mesh.primitives) local.extend(p.bounds());
    for (const Mat4& m : mesh.instances) out.extend(local.transformed(m));
  }
  for (const ImpostorSet& set : impostors) {
    if (!set.atlas) continue;
    Bounds sphere;
    sphere.extend(set.atlas->geometry.center - Vec3::Constant(set.atlas->geometry.radius));
    sphere.extend(set.atlas->geometry.center + Vec3::Constant(set.atlas->geometry.radius));
    for (const Mat4& m : set.instances) out.extend(sphere.transformed(m));
  }
  return out;
}

namespace {
std::size_t count(const Scene& s, Topology t) {
  std::size_t n = 0;
  for (const Mesh& mesh : s.meshes)
    for (const Primitive& p : mesh.primitives)
      if (p.topology == t) n += p.element_count() * mesh.instances.size();
  return n;
}
}  // namespace

std::size_t Scene::triangle_count() const { return count(*this, Topology::kTriangles); }
std::size_t Scene::line_count() const { return count(*this, Topology::kLines); }
std::size_t Scene::point_count() const { return count(*this, Topology::kPoints); }

}  // namespace sylva::render
