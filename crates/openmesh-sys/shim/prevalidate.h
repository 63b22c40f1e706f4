// prevalidate.h: checks of the raw bytes before OpenMesh's readers see them.
//
// OpenMesh 9's readers trust the data. On input they do not expect they loop over counts read
// from the file (or never read: OFF's counts are uninitialised when missing), pushing stale
// values each round, so a few bytes can cost hours and gigabytes; the OM reader asserts on
// chunk headers it does not expect. These checks accept the subset of each format that the
// reader parses to its end without a failed extraction, and fail (omsys::Failure) on the rest,
// so OpenMesh's work stays linear in the size of the data.
#pragma once

#include <cstddef>
#include <cstdint>

namespace omsys {

/// A PLY file (ASCII or binary) whose header OpenMesh parses as written and whose elements up
/// to the face element are all present and well-formed.
void check_ply(const uint8_t *data, std::size_t len);

/// A plain ASCII OFF file ("OFF", counts, vertices, faces) with every declared record present.
void check_off(const uint8_t *data, std::size_t len);

/// An OM 2.0 to 2.2 file whose chunks have the layout OpenMesh 7 to 9 writes, each inside the data.
void check_om(const uint8_t *data, std::size_t len);

}  // namespace omsys
