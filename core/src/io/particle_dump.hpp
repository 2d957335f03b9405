// HDF5 dump of every registered particle field (and the `extra` arrays held outside the registry): the state written when a run is stopped by the
// instability detector (`instability_dump.h5`), so that the blow-up can be inspected with h5dump,
// h5py or ParaView's HDF5 readers at full precision. Layout: one dataset per field under
// /fields/<name>, shape (particles, components), attributes `unit`; root attributes `time_s`,
// `step`, `particles`.
#pragma once

#include <cstddef>
#include <filesystem>

#include "io/particle_array.hpp"
#include "sphforge/fields.hpp"

namespace sphforge::io {

/// Writes (or replaces) `file`. Throws std::runtime_error when HDF5 fails.
void write_particle_dump(const std::filesystem::path& file, const FieldRegistry& fields, std::size_t count,
                         double time_s, long long step, const std::vector<ParticleArray>& extra = {});

}  // namespace sphforge::io
