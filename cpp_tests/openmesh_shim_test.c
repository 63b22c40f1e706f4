/* The C shim of crates/openmesh-sys (openmesh_shim.h) used from C99, built into this test from
 * its source so that the sanitizer build instruments it: every function, the error paths (bad
 * arguments, unreadable, truncated and corrupt data, faces OpenMesh cannot add) and the handle
 * lifetime, with LeakSanitizer on. Checked: statuses, messages, counts, that what is written
 * comes back bit for bit (OM) or as float (PLY), and that triangles and other non-quads are
 * read and written as they are (the shim takes faces of any arity). */
#include "openmesh_shim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;
#define CHECK(cond)                                                   \
  do {                                                                \
    if (!(cond)) {                                                    \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                     \
    }                                                                 \
  } while (0)

static const char kPly[] =
    "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar fixed\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0 1\n1 0 0 0\n2 0 0 0\n0 1 0 0\n1 1 0 0\n2 1.5 0 1\n4 0 1 4 3\n4 1 2 5 4\n";

static OmsysStatus read_text(OmsysMesh *m, const char *text, size_t len, const char *format) {
  return omsys_read(m, (const uint8_t *)text, len, format);
}

static void test_read_ply(void) {
  OmsysMesh *m = omsys_mesh_new();
  OmsysCounts c;
  OmsysReadInfo info;
  double points[18];
  uint32_t offsets[3], indices[8];
  uint8_t fixed[6];
  CHECK(m != NULL);
  CHECK(read_text(m, kPly, sizeof kPly - 1, "PLY") == OMSYS_OK);
  CHECK(strcmp(omsys_mesh_error(m), "") == 0);
  CHECK(omsys_mesh_counts(m, &c) == OMSYS_OK);
  CHECK(c.vertices == 6 && c.faces == 2 && c.face_indices == 8 && c.has_fixed == 1);
  CHECK(omsys_read_info(m, &info) == OMSYS_OK);
  CHECK(info.declared_vertices == 6 && info.declared_faces == 2 && info.face_records == 2);
  CHECK(info.dropped_faces == 0 && info.binary == 0 && info.has_fixed_property == 1);
  /* Wrong lengths are refused, nothing written. */
  CHECK(omsys_mesh_get(m, points, 17, offsets, 3, indices, 8, fixed, 6) == OMSYS_INVALID_ARGUMENT);
  CHECK(omsys_mesh_get(m, points, 18, offsets, 3, indices, 8, NULL, 0) == OMSYS_INVALID_ARGUMENT);
  CHECK(omsys_mesh_get(m, points, 18, offsets, 3, indices, 8, fixed, 6) == OMSYS_OK);
  CHECK(points[15] == 2.0 && points[16] == 1.5 && offsets[0] == 0 && offsets[1] == 4 && offsets[2] == 8);
  CHECK(indices[4] == 1 && indices[5] == 2 && indices[6] == 5 && indices[7] == 4);
  CHECK(fixed[0] == 1 && fixed[1] == 0 && fixed[5] == 1);
  omsys_mesh_free(m);
}

static void test_write_and_read_back(void) {
  /* 1/3 is not a float: OM keeps it, PLY (float x, y, z in OpenMesh 9) rounds it. */
  const double pts[12] = {0, 0, 0, 1.0 / 3.0, 0, 0, 1.0 / 3.0, 1, 0, 0, 1, 1e-300};
  const uint32_t offs[2] = {0, 4}, idx[4] = {0, 1, 2, 3};
  const uint8_t fixed[4] = {0, 1, 0, 1};
  const char *formats[3] = {"om", "ply", "ply"};
  int k;
  for (k = 0; k < 3; ++k) {
    OmsysMesh *w = omsys_mesh_new(), *r = omsys_mesh_new();
    OmsysWriteOptions wo;
    const uint8_t *data = NULL;
    size_t len = 0;
    double back[12];
    uint32_t boffs[2], bidx[4];
    uint8_t bfixed[4];
    OmsysCounts c;
    wo.binary = k == 2;
    CHECK(omsys_mesh_set(w, pts, 4, offs, 1, idx, 4, fixed) == OMSYS_OK);
    CHECK(omsys_write(w, formats[k], &wo) == OMSYS_OK);
    CHECK(omsys_output(w, &data, &len) == OMSYS_OK && len > 0);
    CHECK(omsys_read(r, data, len, formats[k]) == OMSYS_OK);
    CHECK(omsys_mesh_counts(r, &c) == OMSYS_OK && c.vertices == 4 && c.faces == 1 && c.has_fixed);
    CHECK(omsys_mesh_get(r, back, 12, boffs, 2, bidx, 4, bfixed, 4) == OMSYS_OK);
    if (k == 0) {
      CHECK(memcmp(back, pts, sizeof pts) == 0);
    } else {
      CHECK(back[3] == (double)(float)(1.0 / 3.0) && back[11] == 0.0);
    }
    CHECK(memcmp(bidx, idx, sizeof idx) == 0 && memcmp(bfixed, fixed, sizeof fixed) == 0);
    /* OBJ cannot carry the flags. */
    CHECK(omsys_write(w, "obj", &wo) == OMSYS_INVALID_ARGUMENT && strstr(omsys_mesh_error(w), "fixed") != NULL);
    omsys_mesh_free(w);
    omsys_mesh_free(r);
  }
}

static void test_errors(void) {
  OmsysMesh *m = omsys_mesh_new();
  static const char dup[] =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n4 0 1 2 3\n";
  const double pts[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const uint32_t offs[3] = {0, 4, 8}, idx[8] = {0, 1, 2, 3, 0, 1, 2, 3}, bad_idx[4] = {0, 1, 2, 9};
  uint64_t record = 99;
  OmsysDropReason reason = 0;
  OmsysReadInfo info;
  size_t cut;

  CHECK(omsys_read(NULL, (const uint8_t *)"", 0, "ply") == OMSYS_INVALID_ARGUMENT);
  CHECK(read_text(m, kPly, sizeof kPly - 1, "stl") == OMSYS_INVALID_ARGUMENT);
  CHECK(read_text(m, kPly, sizeof kPly - 1, NULL) == OMSYS_INVALID_ARGUMENT);
  CHECK(read_text(m, "", 0, "om") == OMSYS_READ_FAILED && strstr(omsys_mesh_error(m), "OM") != NULL);
  CHECK(read_text(m, "OMPB\1\0\0\0\0\0\0\0\0\0\0\0", 16, "om") == OMSYS_READ_FAILED);
  /* Every cut of the PLY is an error (a cut in the final newline reads the whole mesh). */
  for (cut = 0; cut + 1 < sizeof kPly - 1; ++cut) {
    const OmsysStatus s = read_text(m, kPly, cut, "ply");
    CHECK(s == OMSYS_READ_FAILED || s == OMSYS_INCOMPLETE);
    CHECK(strlen(omsys_mesh_error(m)) > 0);
  }
  /* Every cut of an OFF file, and a binary PLY whose counts the data cannot hold, under the
   * sanitizers: prevalidate.cpp refuses them before OpenMesh's readers loop on them. */
  {
    static const char off[] = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    static const char bin[] =
        "ply\nformat binary_big_endian 1.0\nelement vertex 4000000000\nproperty double x\n"
        "property double y\nproperty double z\nelement face 1\nproperty list int int vertex_indices\n"
        "end_header\n\x7f\xff\xff\xff";
    for (cut = 0; cut + 1 < sizeof off - 1; ++cut) {
      const OmsysStatus s = read_text(m, off, cut, "off");
      CHECK(s == OMSYS_READ_FAILED || s == OMSYS_INCOMPLETE);
    }
    CHECK(read_text(m, off, sizeof off - 1, "off") == OMSYS_OK);
    CHECK(read_text(m, bin, sizeof bin - 1, "ply") == OMSYS_READ_FAILED);
    CHECK(strstr(omsys_mesh_error(m), "truncated") != NULL);
  }
  /* A duplicated face: reported, not added with copies of its vertices. */
  CHECK(read_text(m, dup, sizeof dup - 1, "ply") == OMSYS_INCOMPLETE);
  CHECK(strstr(omsys_mesh_error(m), "face 1") != NULL);
  CHECK(omsys_read_info(m, &info) == OMSYS_OK && info.dropped_faces == 1 && info.face_records == 2);
  CHECK(omsys_dropped_face(m, 0, &record, &reason) == OMSYS_OK && record == 1 && reason == OMSYS_DROP_NON_MANIFOLD);
  CHECK(omsys_dropped_face(m, 1, &record, &reason) == OMSYS_INVALID_ARGUMENT);
  /* Arrays that make no OpenMesh mesh. */
  CHECK(omsys_mesh_set(m, pts, 4, offs, 2, idx, 8, NULL) == OMSYS_INVALID_MESH);
  CHECK(strstr(omsys_mesh_error(m), "face 1") != NULL);
  CHECK(omsys_mesh_set(m, pts, 4, offs, 1, bad_idx, 4, NULL) == OMSYS_INVALID_MESH);
  CHECK(omsys_mesh_set(m, pts, 4, NULL, 1, idx, 4, NULL) == OMSYS_INVALID_ARGUMENT);
  CHECK(omsys_write(m, "xyz", NULL) == OMSYS_INVALID_ARGUMENT);
  CHECK(omsys_mesh_counts(NULL, NULL) == OMSYS_INVALID_ARGUMENT);
  CHECK(strlen(omsys_mesh_error(NULL)) > 0);
  omsys_mesh_free(m);
  omsys_mesh_free(NULL);
}

/* Faces of three, four and five vertices: the shim takes any arity, and OM and PLY (ASCII and
 * binary) give them back as written, nothing dropped. */
static void test_mixed_faces(void) {
  static const char ply[] =
      "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n1 2 0\n4 0 1 4 3\n4 1 2 5 4\n3 3 4 6\n";
  const double pts[27] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0, 0.5, 2, 0, 1.5, 2.5, 0, 2, 2, 0};
  const uint32_t offs[5] = {0, 4, 8, 13, 16};
  const uint32_t idx[16] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 8, 7, 6, 4, 5, 8};
  const char *formats[3] = {"om", "ply", "ply"};
  OmsysMesh *m = omsys_mesh_new();
  OmsysCounts c;
  OmsysReadInfo info;
  double points[27];
  uint32_t boffs[5], bidx[16];
  int k;
  /* A triangle in a PLY file: a 3-vertex face. */
  CHECK(read_text(m, ply, sizeof ply - 1, "ply") == OMSYS_OK);
  CHECK(omsys_mesh_counts(m, &c) == OMSYS_OK && c.vertices == 7 && c.faces == 3 && c.face_indices == 11);
  CHECK(omsys_read_info(m, &info) == OMSYS_OK && info.dropped_faces == 0 && info.face_records == 3);
  CHECK(omsys_mesh_get(m, points, 21, boffs, 4, bidx, 11, NULL, 0) == OMSYS_OK);
  CHECK(boffs[2] == 8 && boffs[3] == 11 && bidx[8] == 3 && bidx[9] == 4 && bidx[10] == 6);
  omsys_mesh_free(m);
  for (k = 0; k < 3; ++k) {
    OmsysMesh *w = omsys_mesh_new(), *r = omsys_mesh_new();
    OmsysWriteOptions wo;
    const uint8_t *data = NULL;
    size_t len = 0;
    wo.binary = k == 2;
    CHECK(omsys_mesh_set(w, pts, 9, offs, 4, idx, 16, NULL) == OMSYS_OK);
    CHECK(omsys_write(w, formats[k], &wo) == OMSYS_OK);
    CHECK(omsys_output(w, &data, &len) == OMSYS_OK && len > 0);
    CHECK(omsys_read(r, data, len, formats[k]) == OMSYS_OK);
    CHECK(omsys_mesh_counts(r, &c) == OMSYS_OK && c.vertices == 9 && c.faces == 4 && c.face_indices == 16);
    CHECK(omsys_mesh_get(r, points, 27, boffs, 5, bidx, 16, NULL, 0) == OMSYS_OK);
    CHECK(memcmp(boffs, offs, sizeof offs) == 0 && memcmp(bidx, idx, sizeof idx) == 0);
    CHECK(memcmp(points, pts, sizeof pts) == 0); /* every coordinate is a float */
    omsys_mesh_free(w);
    omsys_mesh_free(r);
  }
}

int main(void) {
  test_read_ply();
  test_write_and_read_back();
  test_errors();
  test_mixed_faces();
  if (failures) {
    fprintf(stderr, "openmesh_shim_test: %d checks failed\n", failures);
    return 1;
  }
  printf("openmesh_shim_test: all checks passed\n");
  return 0;
}
