// HDF5 dump of every registered particle field (and the `extra` arrays held outside the registry): the state written when a run is stopped by the
// instability detector (`instability_dump.h5`), so that the blow-up can be inspected with h5dump,
// h5py or ParaView's HDF5 readers at full precision. Layout: one dataset per field under
// /fields/<name>, shape (particles, components), attributes `unit`; root attributes `time_s`,
// `step`, `particles`.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "io/particle_array.hpp"
#include "sphforge/fields.hpp"

namespace sphforge::io {

/// Writes (or replaces) `file`. Throws std::runtime_error when HDF5 fails.
void write_particle_dump(const std::filesystem::path& file, const FieldRegistry& fields, std::size_t count,
                         double time_s, long long step, const std::vector<ParticleArray>& extra = {});

/// Version of the checkpoint layout; read_checkpoint() refuses another.
inline constexpr int kCheckpointFormat = 1;

/// A restart checkpoint (`checkpoint_NNNNNN.h5`, docs/checkpoints.md): the dump's layout (every
/// allocated field at full precision) plus the root attribute `checkpoint_format` and the dataset
/// /state, the run's other state as JSON text. Written to `file`.tmp and renamed into place.
/// `extra`: per-particle arrays the engine holds outside the registry, stored like fields.
void write_checkpoint(const std::filesystem::path& file, const FieldRegistry& fields, std::size_t count,
                      double time_s, long long step, const std::string& state_json,
                      const std::vector<ParticleArray>& extra = {});

/// Reads a checkpoint's fields into `fields` (every allocated field must be there with the same
/// shape, for `count` particles) and each array of `extra` (by its name and components) and returns
/// its state text. Throws std::runtime_error saying what does not match.
std::string read_checkpoint(const std::filesystem::path& file, FieldRegistry& fields, std::size_t count,
                            std::vector<ParticleArray>& extra);

}  // namespace sphforge::io
