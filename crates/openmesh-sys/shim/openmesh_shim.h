/* openmesh_shim.h: a C interface to OpenMesh's polygon mesh I/O (OpenMesh 9).
 *
 * The shim owns an OpenMesh::PolyMesh_ArrayKernelT with double-precision points and reads and
 * writes it with OpenMesh::IO from and to memory buffers. The mesh is handed over as flat
 * arrays: points (x, y, z per vertex), faces as offsets into a vertex index array (any arity),
 * and optional per-vertex fixed flags (a vertex property named "fixed", or OM's locked status).
 *
 * Contract: no C++ exception leaves a function of this header; every failure is a status code
 * plus a message (omsys_mesh_error). Functions never read or write past the lengths given.
 * Calls on one handle must not overlap; calls on different handles may run concurrently (the
 * shim serializes OpenMesh's reader and writer singletons, which are not thread-safe).
 */
#ifndef OPENMESH_SHIM_H
#define OPENMESH_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes (int32_t, so that no out-of-range enum value can reach Rust). */
typedef int32_t OmsysStatus;
#define OMSYS_OK 0
/* A null pointer, a buffer of the wrong length, an unknown format. */
#define OMSYS_INVALID_ARGUMENT 1
/* OpenMesh's reader rejected the data, or the data it passed on is inconsistent. */
#define OMSYS_READ_FAILED 2
/* The reader succeeded but the mesh differs from what the file declared (faces OpenMesh could
 * not add, vertices or faces missing): see omsys_read_info and omsys_dropped_face. */
#define OMSYS_INCOMPLETE 3
/* The arrays given to omsys_mesh_set do not make an OpenMesh mesh (bad index, non-manifold). */
#define OMSYS_INVALID_MESH 4
/* OpenMesh's writer failed. */
#define OMSYS_WRITE_FAILED 5
#define OMSYS_OUT_OF_MEMORY 6
/* Any other C++ exception. */
#define OMSYS_INTERNAL 7

/* Why a face record of the file is not in the mesh as the file gave it. */
typedef int32_t OmsysDropReason;
/* Fewer than 3 vertices (OpenMesh ignores such faces). */
#define OMSYS_DROP_TOO_FEW_VERTICES 1
/* A vertex index is negative or not below the number of vertices. */
#define OMSYS_DROP_INVALID_INDEX 2
/* The same vertex appears twice. */
#define OMSYS_DROP_REPEATED_VERTEX 3
/* OpenMesh's add_face refused it: non-manifold vertex or edge, or an edge already used in the
 * same direction (a duplicated or flipped face). OpenMesh's importer would add such a face
 * with copies of its vertices; the shim reports it instead. */
#define OMSYS_DROP_NON_MANIFOLD 4

/* The mesh: OpenMesh's mesh, the flat arrays, the last read's report and output buffer. */
typedef struct OmsysMesh OmsysMesh;

/* A new empty mesh; NULL when out of memory. */
OmsysMesh *omsys_mesh_new(void);
/* Frees a mesh (NULL is allowed). */
void omsys_mesh_free(OmsysMesh *mesh);
/* The message of the last failure on `mesh` ("" after a success); valid until the next call
 * on `mesh`. Never NULL. */
const char *omsys_mesh_error(const OmsysMesh *mesh);

/* Reads a file's bytes with OpenMesh; `format` is the extension without the dot ("ply", "om",
 * "obj", "off"; ASCII case-insensitive). On OMSYS_OK and OMSYS_INCOMPLETE the read report is
 * available; on OMSYS_OK the mesh arrays too. */
OmsysStatus omsys_read(OmsysMesh *mesh, const uint8_t *data, size_t len, const char *format);

/* What the last read saw. */
typedef struct OmsysReadInfo {
  /* Counts the file declared (PLY and OFF headers, OM header, OBJ `v` and `f` lines). */
  uint64_t declared_vertices;
  uint64_t declared_faces;
  /* Vertices and face records the reader passed on. */
  uint64_t vertex_records;
  uint64_t face_records;
  /* Face records that are not in the mesh (see omsys_dropped_face). */
  uint64_t dropped_faces;
  /* The file was binary. */
  int32_t binary;
  /* The file had a vertex property "fixed" / vertex status (locked flags). */
  int32_t has_fixed_property;
  int32_t has_vertex_status;
} OmsysReadInfo;

OmsysStatus omsys_read_info(const OmsysMesh *mesh, OmsysReadInfo *info);
/* The i-th dropped face record: its 0-based index among the file's face records and why. */
OmsysStatus omsys_dropped_face(const OmsysMesh *mesh, size_t i, uint64_t *record, OmsysDropReason *reason);

/* Sizes of the mesh arrays. */
typedef struct OmsysCounts {
  size_t vertices;
  size_t faces;
  size_t face_indices;
  int32_t has_fixed;
} OmsysCounts;

OmsysStatus omsys_mesh_counts(const OmsysMesh *mesh, OmsysCounts *counts);
/* Copies the arrays out: points (3 * vertices), face_offsets (faces + 1, starting at 0),
 * face_indices, fixed (vertices; may be NULL with fixed_len 0 when has_fixed is 0). Each
 * length must equal the count exactly. Faces list their vertices as OpenMesh's face-vertex
 * circulator does (the file's order for PLY, OBJ and OFF). */
OmsysStatus omsys_mesh_get(const OmsysMesh *mesh, double *points, size_t points_len, uint32_t *face_offsets,
                           size_t face_offsets_len, uint32_t *face_indices, size_t face_indices_len,
                           uint8_t *fixed, size_t fixed_len);
/* Replaces the mesh by the given arrays (lengths as for omsys_mesh_get; fixed may be NULL). */
OmsysStatus omsys_mesh_set(OmsysMesh *mesh, const double *points, size_t vertex_count, const uint32_t *face_offsets,
                           size_t face_count, const uint32_t *face_indices, size_t face_indices_len,
                           const uint8_t *fixed);

typedef struct OmsysWriteOptions {
  /* Binary PLY (little endian) instead of ASCII; OM is always binary, OBJ and OFF ASCII. */
  int32_t binary;
} OmsysWriteOptions;

/* Writes the mesh with OpenMesh into the mesh's output buffer (omsys_output). ASCII numbers
 * are written with 17 significant digits. The fixed flags, when the mesh has them, go into a
 * vertex property "fixed" (int in PLY, uchar in OM) and, in OM, also into the vertices' locked
 * status; OBJ and OFF cannot carry them (OMSYS_INVALID_ARGUMENT). */
OmsysStatus omsys_write(OmsysMesh *mesh, const char *format, const OmsysWriteOptions *options);
/* The bytes of the last successful omsys_write; valid until the next call on `mesh`. */
OmsysStatus omsys_output(const OmsysMesh *mesh, const uint8_t **data, size_t *len);

#ifdef __cplusplus
}
#endif

#endif /* OPENMESH_SHIM_H */
