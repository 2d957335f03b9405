// Structure-of-arrays particle storage with a named-field registry.
//
// A field exists only if some pass of the pipeline (or a plugin) declared that it reads or
// writes it; `allocate()` then creates exactly those arrays. An isothermal case therefore has
// no "temperature" array at all, and a rate-independent material no "plastic_strain_rate".
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace sphforge {

enum class FieldType { Float64, Int64 };

struct FieldInfo {
  std::string name;        ///< e.g. "position", "deviatoric_stress"
  int components = 1;      ///< 1 scalar, 3 vector, 6 symmetric tensor (xx yy zz xy yz xz), 9 tensor
  std::string unit = "1";  ///< SI unit, written to the output files
  FieldType type = FieldType::Float64;
  bool output = true;      ///< written to particles_*.vtu
};

/// Why a field is wanted; recorded so that `sphforge check` can explain allocations.
enum class Access { Read, Write, ReadWrite };

class FieldRegistry {
 public:
  /// Declares that `who` reads and/or writes the field. Declaring the same name twice with a
  /// different shape throws std::logic_error (a programming error, not a user error).
  void declare(const FieldInfo& info, const std::string& who, Access access = Access::ReadWrite);

  /// Allocates every declared field for `count` particles (zero-filled). Later `resize` keeps data.
  void allocate(std::size_t count);
  void resize(std::size_t count);
  std::size_t size() const { return count_; }

  bool declared(const std::string& name) const { return fields_.count(name) != 0; }
  bool allocated(const std::string& name) const;

  /// Pointer to the first component of particle 0; particle i, component c is at [i*components + c].
  double* f64(const std::string& name);
  const double* f64(const std::string& name) const;
  std::int64_t* i64(const std::string& name);
  const std::int64_t* i64(const std::string& name) const;
  /// Same, but nullptr when the field was not declared (optional fields).
  double* f64_if(const std::string& name);
  const double* f64_if(const std::string& name) const;

  const FieldInfo& info(const std::string& name) const;
  std::vector<std::string> names() const;  ///< declared fields, sorted
  const std::vector<std::string>& declared_by(const std::string& name) const;

  /// Applies `new_index_of_old` ... as new[i] = old[order[i]] to every field (locality reordering).
  void permute(std::span<const std::size_t> order);

  std::size_t bytes() const;  ///< memory held by all allocated arrays

 private:
  struct Field {
    FieldInfo info;
    std::vector<double> f;
    std::vector<std::int64_t> i;
    std::vector<std::string> users;
    bool allocated = false;
  };
  Field& get(const std::string& name);
  const Field& get(const std::string& name) const;
  std::map<std::string, Field> fields_;
  std::size_t count_ = 0;
};

/// Names of the fields the core itself uses (plugins may use any other names they declare).
namespace field {
inline constexpr const char* id = "id";                          // Int64, stable particle id
inline constexpr const char* body = "body";                      // Int64, body index
inline constexpr const char* position = "position";              // m
inline constexpr const char* velocity = "velocity";              // m/s
inline constexpr const char* acceleration = "acceleration";      // m/s^2
inline constexpr const char* mass = "mass";                      // kg
inline constexpr const char* density = "density";                // kg/m^3
inline constexpr const char* density_rate = "density_rate";      // kg/m^3/s
inline constexpr const char* pressure = "pressure";              // Pa
inline constexpr const char* deviatoric_stress = "deviatoric_stress";    // Pa, 6 comps
// velocity_gradient holds L for the material update of the step (MaterialBatch); after it the step
// reuses its storage for sigma C (docs/theory.md section 7), and an output frame recomputes L for
// the state it shows. A plugin that needs L elsewhere computes it; density_rate and
// gradient_condition are output arrays of the frames, not fields.
inline constexpr const char* velocity_gradient = "velocity_gradient";    // 1/s, 9 comps L_ab = dv_a/dx_b
inline constexpr const char* gradient_condition = "gradient_condition";  // 1, cond(M), -1 where uncorrected
inline constexpr const char* contact_force = "contact_force";    // N
inline constexpr const char* temperature = "temperature";        // K
inline constexpr const char* temperature_rate = "temperature_rate";  // K/s
inline constexpr const char* heat_source = "heat_source";        // W/kg, plastic (material) heat
inline constexpr const char* convection_coefficient = "convection_coefficient";  // W/(m^2 K), free surfaces
inline constexpr const char* plastic_strain = "plastic_strain";  // 1
inline constexpr const char* von_mises_stress = "von_mises_stress";  // Pa
// 1 where the particle's material criterion has failed it (latched), else 0; declared by a material
// that has a failure criterion, and read by the core's bond rule (docs/failure.md, theory eq. 110).
inline constexpr const char* failed = "failed";
// m, the particle's own smoothing length h_over_dx s_i; only in a scene of several spacings
// (docs/theory.md section 19), which the core detects from the bodies' spacings.
inline constexpr const char* smoothing_length = "smoothing_length";
}  // namespace field

}  // namespace sphforge
