// A triangle mesh of the vessel surface g = 0 for display (rviz, files).
// Declared and documented in endovascular_sim/geometry/surface_mesh.h.
#include "endovascular_sim/geometry/surface_mesh.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <unordered_map>

namespace evsim {
namespace {

using Key = int64_t;

Key latticeKey(int64_t x, int64_t y, int64_t z) {
  return ((x + (1 << 20)) << 42) | ((y + (1 << 20)) << 21) | (z + (1 << 20));
}

// Cube corners (bit 0: x, bit 1: y, bit 2: z) and six tetrahedra sharing the
// diagonal 0-7.
const int kTets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7},
                         {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};

class Mesher {
 public:
  Mesher(const VesselField& f, double h, double r, const MotionSnapshot& m)
      : field_(f), h_(h), r_(r), motion_(m) {}

  void cube(int64_t x, int64_t y, int64_t z) {
    Key keys[8];
    double values[8];
    Vec3 points[8];
    bool any_in = false, any_out = false;
    for (int c = 0; c < 8; ++c) {
      const int64_t cx = x + (c & 1), cy = y + ((c >> 1) & 1), cz = z + ((c >> 2) & 1);
      keys[c] = latticeKey(cx, cy, cz);
      points[c] = Vec3(cx * h_, cy * h_, cz * h_);
      values[c] = value(keys[c], points[c]);
      (values[c] >= 0.0 ? any_in : any_out) = true;
    }
    if (!(any_in && any_out)) return;
    for (const auto& t : kTets) tetrahedron(t, keys, values, points);
  }

  SurfaceMesh mesh;

 private:
  double value(Key k, const Vec3& p) {
    const auto it = values_.find(k);
    if (it != values_.end()) return it->second;
    const double v = field_.evaluate(p, r_, motion_).value;
    values_.emplace(k, v);
    return v;
  }

  int vertexOnEdge(Key ka, Key kb, double va, double vb, const Vec3& pa, const Vec3& pb) {
    const double t = va / (va - vb);
    // A crossing at a lattice point is one vertex for every edge through it.
    if (t < 1e-7 || t > 1.0 - 1e-7) {
      const bool at_a = t < 1e-7;
      const Key k = at_a ? ka : kb;
      const auto it = point_vertices_.find(k);
      if (it != point_vertices_.end()) return it->second;
      const int id = addVertex(at_a ? pa : pb);
      point_vertices_.emplace(k, id);
      return id;
    }
    const std::pair<Key, Key> e = ka < kb ? std::make_pair(ka, kb) : std::make_pair(kb, ka);
    const auto it = edge_vertices_.find(e);
    if (it != edge_vertices_.end()) return it->second;
    const int id = addVertex(pa + t * (pb - pa));
    edge_vertices_.emplace(e, id);
    return id;
  }

  int addVertex(const Vec3& p) {
    const Vec3 g = field_.evaluate(p, r_, motion_).gradient;
    mesh.vertices.push_back(p);
    mesh.normals.push_back(g.norm() > 0 ? Vec3(-g.normalized()) : Vec3::UnitZ());
    return static_cast<int>(mesh.vertices.size()) - 1;
  }

  void triangle(int a, int b, int c, const Vec3& outward) {
    if (a == b || b == c || a == c) return;  // collapsed at a lattice point
    const Vec3 n = (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
    if (n.squaredNorm() == 0.0) return;
    if (n.dot(outward) < 0.0) std::swap(b, c);
    mesh.triangles.emplace_back(a, b, c);
  }

  void tetrahedron(const int t[4], const Key* keys, const double* v, const Vec3* p) {
    int in[4], out[4], ni = 0, no = 0;
    for (int k = 0; k < 4; ++k) (v[t[k]] >= 0.0 ? in[ni++] : out[no++]) = t[k];
    if (ni == 0 || no == 0) return;
    auto edge = [&](int a, int b) {
      return vertexOnEdge(keys[a], keys[b], v[a], v[b], p[a], p[b]);
    };
    Vec3 c_in = Vec3::Zero(), c_out = Vec3::Zero();
    for (int k = 0; k < ni; ++k) c_in += p[in[k]] / ni;
    for (int k = 0; k < no; ++k) c_out += p[out[k]] / no;
    const Vec3 outward = c_out - c_in;
    if (ni == 1 || no == 1) {
      const int lone = ni == 1 ? in[0] : out[0];
      const int* rest = ni == 1 ? out : in;
      triangle(edge(lone, rest[0]), edge(lone, rest[1]), edge(lone, rest[2]), outward);
    } else {  // two in, two out: a quad
      const int a = edge(in[0], out[0]), b = edge(in[0], out[1]);
      const int c = edge(in[1], out[1]), d = edge(in[1], out[0]);
      triangle(a, b, c, outward);
      triangle(a, c, d, outward);
    }
  }

  const VesselField& field_;
  double h_, r_;
  const MotionSnapshot& motion_;
  std::unordered_map<Key, double> values_;
  struct PairHash {
    size_t operator()(const std::pair<Key, Key>& e) const {
      return std::hash<Key>()(e.first * 1000003) ^ std::hash<Key>()(e.second);
    }
  };
  std::unordered_map<std::pair<Key, Key>, int, PairHash> edge_vertices_;
  std::unordered_map<Key, int> point_vertices_;
};

}  // namespace

SurfaceMesh meshVesselSurface(const VesselField& field, double spacing, double device_radius,
                              const MotionSnapshot& motion) {
  if (field.bounds().isEmpty()) return {};
  const std::vector<Eigen::AlignedBox3d> cells = field.occupiedCells();
  double h = spacing;
  if (h <= 0.0) {
    // A quarter of the thinnest radius, coarsened to at most ~4e6 cubes.
    const double budget = 4e6;
    h = std::max(field.minRadius() / 4.0, 5e-5);
    const double cubes = cells.size() * std::pow(field.cellSize() / h, 3);
    if (cubes > budget) h *= std::cbrt(cubes / budget);
  }
  Mesher mesher(field, h, device_radius, motion);
  // Each lattice cube belongs to the grid cell holding its centre; cubes in
  // cells without primitives are outside the vessels and skipped.
  for (const auto& cell : cells) {
    const Eigen::Vector3i lo = (cell.min() / h - Vec3::Constant(0.5)).array().ceil().cast<int>();
    const Eigen::Vector3i hi = (cell.max() / h - Vec3::Constant(0.5)).array().ceil().cast<int>();
    for (int64_t z = lo.z(); z < hi.z(); ++z)
      for (int64_t y = lo.y(); y < hi.y(); ++y)
        for (int64_t x = lo.x(); x < hi.x(); ++x) mesher.cube(x, y, z);
  }
  return std::move(mesher.mesh);
}

bool writeMesh(const SurfaceMesh& mesh, const std::string& path, std::string* why) {
  const bool stl = path.size() > 4 && path.compare(path.size() - 4, 4, ".stl") == 0;
  const bool ply = path.size() > 4 && path.compare(path.size() - 4, 4, ".ply") == 0;
  if (!stl && !ply) {
    *why = "the output must end in .ply or .stl: " + path;
    return false;
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) {
    *why = "cannot write " + path;
    return false;
  }
  if (ply) {
    out << "ply\nformat ascii 1.0\ncomment endovascular_sim vessel surface, metres\n"
        << "element vertex " << mesh.vertices.size()
        << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property float nx\nproperty float ny\nproperty float nz\n"
        << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\n"
        << "end_header\n";
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Vec3& p = mesh.vertices[i];
      const Vec3& n = mesh.normals[i];
      out << p.x() << " " << p.y() << " " << p.z() << " " << n.x() << " " << n.y() << " " << n.z()
          << "\n";
    }
    for (const auto& t : mesh.triangles)
      out << "3 " << t.x() << " " << t.y() << " " << t.z() << "\n";
  } else {
    char header[80] = "endovascular_sim vessel surface, metres";
    out.write(header, 80);
    const uint32_t n = static_cast<uint32_t>(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : mesh.triangles) {
      const Vec3 &a = mesh.vertices[t.x()], &b = mesh.vertices[t.y()], &c = mesh.vertices[t.z()];
      const Vec3 normal = (b - a).cross(c - a).normalized();
      float f[12];
      for (int k = 0; k < 3; ++k) {
        f[k] = static_cast<float>(normal[k]);
        f[3 + k] = static_cast<float>(a[k]);
        f[6 + k] = static_cast<float>(b[k]);
        f[9 + k] = static_cast<float>(c[k]);
      }
      out.write(reinterpret_cast<const char*>(f), sizeof(f));
      const uint16_t attr = 0;
      out.write(reinterpret_cast<const char*>(&attr), 2);
    }
  }
  if (!out) {
    *why = "writing " + path + " failed";
    return false;
  }
  return true;
}

}  // namespace evsim
