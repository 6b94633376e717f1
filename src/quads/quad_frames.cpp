// Quad frames: per-face frames made consistent by breadth-first traversal (section 3.3 of Sarkar
// et al. 2017), seeds at face centres and overlap offsets.
#include <pcl_patchdict/quads/quad_frames.h>

#include <pcl_patchdict/core/error.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <string>

namespace pcl {
namespace patchdict {

Eigen::Vector3d transportTangent(const Eigen::Vector3d& v, const Eigen::Vector3d& from_normal,
                                 const Eigen::Vector3d& to_normal)
{
  // Rodrigues rotation about from × to by the angle between the normals (the discrete
  // Levi-Civita transport across an edge); antiparallel normals fall back to a projection.
  const Eigen::Vector3d axis = from_normal.cross(to_normal);
  const double sine = axis.norm(), cosine = from_normal.dot(to_normal);
  Eigen::Vector3d out;
  if (sine < 1e-12) {
    out = v - to_normal * to_normal.dot(v);
  } else {
    const Eigen::Vector3d k = axis / sine;
    out = v * cosine + k.cross(v) * sine + k * k.dot(v) * (1.0 - cosine);
    out -= to_normal * to_normal.dot(out);  // remove rounding off the plane
  }
  const double length = out.norm();
  return length > 0.0 ? Eigen::Vector3d(out / length) : out;
}

double transportedXAngle(const Eigen::Matrix3d& frame_a, const Eigen::Matrix3d& frame_b)
{
  const Eigen::Vector3d xb = transportTangent(frame_b.row(0).transpose(), frame_b.row(2).transpose(),
                                              frame_a.row(2).transpose());
  if (xb.squaredNorm() == 0.0)
    return std::acos(0.0);
  return std::acos(std::clamp(frame_a.row(0).dot(xb.transpose()), -1.0, 1.0));
}

namespace {

/** Unit normal oriented like the mean of the vertex normals (when the mesh has them). */
Eigen::Vector3d orientedFaceNormal(const QuadMesh& mesh, std::size_t f)
{
  Eigen::Vector3d n = mesh.faceNormal(f);
  if (mesh.normals.size() == mesh.vertices.size()) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const std::int32_t v : mesh.faces[f])
      mean += mesh.normals[v];
    if (n.dot(mean) < 0.0)
      n = -n;
  }
  return n;
}

/** First side direction in the face plane: for a quad, the bisector of its two side directions
  * (each the mean of two opposite sides); the first side otherwise. Zero when degenerate. */
Eigen::Vector3d sideDirection(const QuadMesh& mesh, std::size_t f, const Eigen::Vector3d& z)
{
  const auto& face = mesh.faces[f];
  const auto unitInPlane = [&](Eigen::Vector3d v) {
    v -= z * z.dot(v);
    const double length = v.norm();
    return length > 0.0 ? Eigen::Vector3d(v / length) : Eigen::Vector3d::Zero();
  };
  Eigen::Vector3d d = unitInPlane(mesh.vertices[face[1]] - mesh.vertices[face[0]]);
  if (face.size() == 4) {
    // All four sides: the X of the pair 0→1, 3→2 and the X implied by the pair 0→3, 1→2 (Y × Z),
    // bisected, so a skewed quad gets the orthogonal frame closest to both of its side directions.
    const Eigen::Vector3d a = unitInPlane(mesh.vertices[face[1]] - mesh.vertices[face[0]] +
                                          mesh.vertices[face[2]] - mesh.vertices[face[3]]);
    const Eigen::Vector3d b = unitInPlane(mesh.vertices[face[3]] - mesh.vertices[face[0]] +
                                          mesh.vertices[face[2]] - mesh.vertices[face[1]]);
    d = a + b.cross(z);
  }
  d -= z * z.dot(d);
  const double length = d.norm();
  return length > 0.0 ? Eigen::Vector3d(d / length) : Eigen::Vector3d::Zero();
}

void checkQuadMesh(const QuadMesh& mesh)
{
  if (mesh.faces.empty())
    throw Error("quad frames: the quad mesh has no faces");
  const std::int64_t num_vertices = static_cast<std::int64_t>(mesh.vertices.size());
  for (const auto& face : mesh.faces) {
    if (face.size() < 3)
      throw Error("quad frames: a face has fewer than three vertices");
    for (const std::int32_t v : face)
      if (v < 0 || v >= num_vertices)
        throw Error("quad frames: face index " + std::to_string(v) + " is out of range");
  }
}

/** Faces sharing an edge, in increasing order (deterministic traversal). */
std::vector<std::vector<std::int32_t>> faceAdjacency(const QuadMesh& mesh)
{
  const std::size_t num_faces = mesh.faces.size();
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::int32_t>> edge_faces;
  for (std::size_t f = 0; f < num_faces; ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t k = 0; k < face.size(); ++k) {
      const std::int32_t a = face[k], b = face[(k + 1) % face.size()];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(static_cast<std::int32_t>(f));
    }
  }
  std::vector<std::vector<std::int32_t>> adjacent(num_faces);
  for (const auto& [edge, faces] : edge_faces)
    for (const std::int32_t f : faces)
      for (const std::int32_t g : faces)
        if (f != g)
          adjacent[f].push_back(g);
  for (auto& list : adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return adjacent;
}

/** Per face: its normal z, a side direction d0, whether it has both, and its frame once set. */
struct FaceFrames {
  std::vector<Eigen::Vector3d> z, d0;
  std::vector<char> valid, done;
  std::vector<Eigen::Matrix3d> frames;

  explicit FaceFrames(const QuadMesh& mesh)
  {
    const std::size_t num_faces = mesh.faces.size();
    z.resize(num_faces);
    d0.resize(num_faces);
    valid.assign(num_faces, 0);
    for (std::size_t f = 0; f < num_faces; ++f) {
      z[f] = orientedFaceNormal(mesh, f);
      d0[f] = z[f].squaredNorm() > 0.0 ? sideDirection(mesh, f, z[f]) : Eigen::Vector3d::Zero();
      valid[f] = d0[f].squaredNorm() > 0.0;
    }
    frames.assign(num_faces, Eigen::Matrix3d::Zero());
    done.assign(num_faces, 0);
  }
  void set(std::size_t f, const Eigen::Vector3d& x)
  {
    frames[f].row(0) = x;
    frames[f].row(1) = z[f].cross(x);
    frames[f].row(2) = z[f];
    done[f] = 1;
  }
};

/** Breadth-first from each unvisited valid face: a child takes the side direction closest to its
  * parent's X transported into its plane. */
void propagateFrames(const std::vector<std::vector<std::int32_t>>& adjacent, FaceFrames& s)
{
  const std::size_t num_faces = adjacent.size();
  for (std::size_t root = 0; root < num_faces; ++root) {
    if (s.done[root] || !s.valid[root])
      continue;
    s.set(root, s.d0[root]);
    std::queue<std::int32_t> queue;
    queue.push(static_cast<std::int32_t>(root));
    while (!queue.empty()) {
      const std::int32_t parent = queue.front();
      queue.pop();
      const Eigen::Vector3d parent_x = s.frames[parent].row(0).transpose();
      for (const std::int32_t child : adjacent[parent]) {
        if (s.done[child] || !s.valid[child])
          continue;
        // Parent's X transported into the child's plane; the closest of the four side directions.
        const Eigen::Vector3d target = transportTangent(parent_x, s.z[parent], s.z[child]);
        const Eigen::Vector3d d1 = s.z[child].cross(s.d0[child]);
        const Eigen::Vector3d candidates[4] = {s.d0[child], d1, -s.d0[child], -d1};
        int best = 0;
        for (int k = 1; k < 4; ++k)
          if (candidates[k].dot(target) > candidates[best].dot(target))
            best = k;
        s.set(child, candidates[best]);
        queue.push(child);
      }
    }
  }
}

/** The traversal leaves seams where its fronts meet with different turns around singularities.
  * Iterated conditional modes shorten them: each face takes, of its four side directions, the one
  * that agrees (within 20°) with the most neighbours, ties kept as they are; sweeps in face order
  * until nothing changes (a local minimum of the number of disagreeing pairs). */
void shortenSeams(const std::vector<std::vector<std::int32_t>>& adjacent, FaceFrames& s)
{
  const std::size_t num_faces = adjacent.size();
  const double agree = std::cos(20.0 * 3.14159265358979323846 / 180.0);
  for (int sweep = 0; sweep < 100; ++sweep) {
    bool changed = false;
    for (std::size_t f = 0; f < num_faces; ++f) {
      if (!s.done[f] || adjacent[f].empty())
        continue;
      const Eigen::Vector3d d1 = s.z[f].cross(s.d0[f]);
      const Eigen::Vector3d candidates[4] = {s.d0[f], d1, -s.d0[f], -d1};
      int votes[4] = {0, 0, 0, 0};
      for (const std::int32_t g : adjacent[f]) {
        if (!s.done[g])
          continue;
        const Eigen::Vector3d x = transportTangent(s.frames[g].row(0).transpose(), s.z[g], s.z[f]);
        if (x.squaredNorm() == 0.0)
          continue;
        for (int k = 0; k < 4; ++k)
          votes[k] += candidates[k].dot(x) > agree;
      }
      const Eigen::Vector3d current = s.frames[f].row(0).transpose();
      int now = 0;
      for (int k = 1; k < 4; ++k)
        if (candidates[k].dot(current) > candidates[now].dot(current))
          now = k;
      int best = now;
      for (int k = 0; k < 4; ++k)
        if (votes[k] > votes[best])
          best = k;
      if (best != now) {
        s.set(f, candidates[best]);
        changed = true;
      }
    }
    if (!changed)
      break;
  }
}

}  // namespace

std::vector<Eigen::Matrix3d> computeQuadFaceFrames(const QuadMesh& mesh)
{
  checkQuadMesh(mesh);
  FaceFrames state(mesh);
  const std::vector<std::vector<std::int32_t>> adjacent = faceAdjacency(mesh);
  propagateFrames(adjacent, state);
  shortenSeams(adjacent, state);
  return std::move(state.frames);
}

void computeQuadFrames(const QuadMesh& mesh, int overlap, std::vector<Eigen::Vector3d>& seeds,
                       std::vector<Eigen::Matrix3d>& frames, std::vector<std::int32_t>* seed_faces)
{
  if (overlap < 0 || overlap > 16)
    throw Error("quad frames: the overlap level must be in [0, 16], got " + std::to_string(overlap));
  const std::vector<Eigen::Matrix3d> face_frames = computeQuadFaceFrames(mesh);
  seeds.clear();
  frames.clear();
  if (seed_faces)
    seed_faces->clear();
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (face_frames[f].isZero())
      continue;
    // Rounded to float, as when frames passed through pcl::ReferenceFrame: the height maps, and
    // the frames a version-3 .pdc decoder re-derives, stay the ones measured (core/local_frame.h).
    const Eigen::Matrix3d frame = roundToSinglePrecision(face_frames[f]);
    const auto& face = mesh.faces[f];
    const Eigen::Vector3d centre = mesh.faceCentre(f);
    const auto emit = [&](const Eigen::Vector3d& seed) {
      seeds.push_back(seed);
      frames.push_back(frame);
      if (seed_faces)
        seed_faces->push_back(static_cast<std::int32_t>(f));
    };
    emit(centre);
    for (int j = 1; j <= overlap; ++j) {
      const double t = 0.5 * j / (overlap + 1.0);
      if (face.size() == 4) {
        // Bilinear patch p(u, v) = (1−u)(1−v)·p0 + u(1−v)·p1 + u·v·p2 + (1−u)·v·p3.
        const Eigen::Vector3d &p0 = mesh.vertices[face[0]], &p1 = mesh.vertices[face[1]],
                              &p2 = mesh.vertices[face[2]], &p3 = mesh.vertices[face[3]];
        for (const double su : {-1.0, 1.0})
          for (const double sv : {-1.0, 1.0}) {
            const double u = 0.5 + su * t, v = 0.5 + sv * t;
            emit((1 - u) * (1 - v) * p0 + u * (1 - v) * p1 + u * v * p2 + (1 - u) * v * p3);
          }
      } else {
        // Other faces: towards four of their corners (repeating corners for triangles).
        for (int c = 0; c < 4; ++c) {
          const Eigen::Vector3d& corner = mesh.vertices[face[static_cast<std::size_t>(c) % face.size()]];
          emit(centre + 2.0 * t * (corner - centre));
        }
      }
    }
  }
}

}  // namespace patchdict
}  // namespace pcl
