// Reading and writing meshes and clouds: PLY (ASCII / binary), OBJ, OFF, STL (ASCII / binary), PCD.
// Every reader validates what it reads and throws pcl::patchdict::Error with one clear line.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/quads/quad_mesh.h>

#include <pcl/PCLPointCloud2.h>

#include <Eigen/Geometry>

#include <string>

namespace pcl {
namespace patchdict {

enum class MeshFormat { Unknown, PLY, OBJ, OFF, STL, PCD };

/** Format from the file name's extension (case-insensitive); Unknown if not recognised. */
MeshFormat formatFromPath(const std::string& path);
/** Lower-case name of a format ("ply", "obj", ...). */
std::string formatName(MeshFormat format);

/** What a reader saw that a user may want to know (nothing in it is an error). */
struct ReadInfo {
  MeshFormat format = MeshFormat::Unknown;
  bool binary = false;
  std::size_t polygons_triangulated = 0;  ///< faces with more than 3 corners, fan-split
  std::size_t lines_ignored = 0;          ///< OBJ records that carry no geometry (mtllib, usemtl, s, o, g, vt, ...)
  std::size_t points_dropped = 0;         ///< PCD: non-finite points left out of the mesh
};

/** \brief Read a mesh or cloud; the format comes from the extension.
  * Rejects (throws Error): missing/unreadable/empty files, truncated data, malformed records,
  * face indices out of range, non-finite vertex coordinates (PCD: NaN points are dropped instead,
  * as depth sensors write them), files without a single vertex. A file without faces gives a mesh
  * with no faces (a cloud). Polygons are fan-triangulated; STL corners with bit-identical positions
  * are merged into one vertex. Normals that are not all finite are dropped, not an error. */
void readMesh(const std::string& path, TriangleMesh& mesh, ReadInfo* info = nullptr);
/** The same for a file's bytes held in memory, in the given format (PLY, OBJ, OFF or STL: PCL reads
  * PCD only from a file, so PCD is an Error here); `name` is what error messages call it. */
void readMeshFromMemory(const std::string& bytes, MeshFormat format, TriangleMesh& mesh, ReadInfo* info = nullptr,
                        const std::string& name = "<memory>");

struct WriteOptions {
  /** PLY and STL: binary little-endian (default) or ASCII. PCD: binary or ASCII. */
  bool binary = true;
  /** Write per-vertex normals when the mesh has them (PLY, OBJ, PCD). */
  bool write_normals = true;
};

/** \brief Write a mesh or cloud; the format comes from the extension.
  * Text formats print coordinates in the shortest form that reads back to the same double, and
  * binary PLY uses float32 only when no coordinate needs more, so PLY, OBJ, OFF and ASCII STL
  * round-trip exactly. Binary STL and PCD store float32: exact only for float-representable
  * coordinates. STL keeps triangles only (no faces: Error), PCD points only, OFF no normals.
  * The file is written to a temporary file in the target directory and renamed into place: it
  * appears whole or not at all. Throws Error, also for a mesh no reader would take back (no
  * vertices, non-finite coordinates, face indices out of range). */
void writeMesh(const std::string& path, const TriangleMesh& mesh, const WriteOptions& options = {});

/** \brief A PCD cloud with every field it holds (colour, intensity, labels, …), its organisation
  * (width × height, NaN points kept) and its viewpoint — for tools that change a few fields and
  * must carry the rest. The file is checked as readMesh checks it; x, y and z must be single
  * float32 or float64 fields. Throws Error with one line naming the file otherwise. */
void readPointCloudBlob(const std::string& path, pcl::PCLPointCloud2& blob, Eigen::Vector4f& origin,
                        Eigen::Quaternionf& orientation);
/** Writes a binary PCD atomically (whole file or nothing, as writeMesh). */
void writePointCloudBlob(const std::string& path, const pcl::PCLPointCloud2& blob, const Eigen::Vector4f& origin,
                         const Eigen::Quaternionf& orientation);

/** Writes a quad (polygon) mesh as OBJ (.obj) or ASCII PLY (.ply), atomically; throws Error for any
  * other extension or a write failure. Vertices are written with 17 significant digits. */
void writeQuadMesh(const std::string& path, const QuadMesh& mesh);

}  // namespace patchdict
}  // namespace pcl
