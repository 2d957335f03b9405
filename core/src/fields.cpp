#include "sphforge/fields.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace sphforge {

namespace {

const char* type_name(FieldType type) { return type == FieldType::Float64 ? "Float64" : "Int64"; }

std::string shape(const FieldInfo& info) {
  return std::to_string(info.components) + " x " + type_name(info.type);
}

// Gathers new[i] = old[order[i]] (whole particles, `comps` values each) into `scratch` and
// copies it back. Copying back (rather than swapping buffers) keeps every field's capacity
// as it was: swapping would hand a 9-component buffer to a scalar field. The scratch buffer
// grows to the largest field once and is reused for all fields of its element type.
template <typename T>
void gather(std::vector<T>& data, std::vector<T>& scratch, std::span<const std::size_t> order,
            int comps) {
  if (scratch.size() < data.size()) scratch.resize(data.size());
  const std::size_t c = static_cast<std::size_t>(comps);
  for (std::size_t i = 0; i < order.size(); ++i)
    std::copy_n(data.data() + order[i] * c, c, scratch.data() + i * c);
  std::copy_n(scratch.data(), data.size(), data.data());
}

}  // namespace

void FieldRegistry::declare(const FieldInfo& info, const std::string& who, Access /*access*/) {
  if (info.name.empty()) throw std::logic_error("field declared by '" + who + "' has no name");
  if (info.components < 1)
    throw std::logic_error("field '" + info.name + "' declared by '" + who +
                           "' with components = " + std::to_string(info.components));
  auto [it, inserted] = fields_.try_emplace(info.name);
  Field& f = it->second;
  if (inserted) {
    f.info = info;
  } else {
    if (f.info.components != info.components || f.info.type != info.type)
      throw std::logic_error("field '" + info.name + "' declared by '" + who + "' as " +
                             shape(info) + " but already declared as " + shape(f.info) + " by " +
                             (f.users.empty() ? std::string("?") : "'" + f.users.front() + "'"));
    // A reader that only knows the shape may declare with the default unit "1" before the
    // writer that knows the real unit; the specific unit wins regardless of order.
    if (f.info.unit == "1" && info.unit != "1") f.info.unit = info.unit;
  }
  if (std::find(f.users.begin(), f.users.end(), who) == f.users.end()) f.users.push_back(who);
}

void FieldRegistry::allocate(std::size_t count) {
  for (auto& [name, f] : fields_) {
    const std::size_t n = count * static_cast<std::size_t>(f.info.components);
    // assign() zero-fills even the part that survives from an earlier allocation.
    if (f.info.type == FieldType::Float64)
      f.f.assign(n, 0.0);
    else
      f.i.assign(n, 0);
    f.allocated = true;
  }
  count_ = count;
}

void FieldRegistry::resize(std::size_t count) {
  // Also allocates fields declared since the last allocate(), so every allocated array always
  // holds size() particles.
  for (auto& [name, f] : fields_) {
    const std::size_t n = count * static_cast<std::size_t>(f.info.components);
    if (f.info.type == FieldType::Float64)
      f.f.resize(n, 0.0);
    else
      f.i.resize(n, 0);
    f.allocated = true;
  }
  count_ = count;
}

bool FieldRegistry::allocated(const std::string& name) const {
  const auto it = fields_.find(name);
  return it != fields_.end() && it->second.allocated;
}

FieldRegistry::Field& FieldRegistry::get(const std::string& name) {
  return const_cast<Field&>(std::as_const(*this).get(name));
}

const FieldRegistry::Field& FieldRegistry::get(const std::string& name) const {
  const auto it = fields_.find(name);
  if (it == fields_.end())
    throw std::logic_error("field '" + name + "' was not declared by any pass or plugin");
  return it->second;
}

namespace {
// Shared checks of the typed accessors; `want` is the element type the caller asked for.
template <typename FieldT>
void check_access(const FieldT& f, const std::string& name, FieldType want) {
  if (f.info.type != want)
    throw std::logic_error("field '" + name + "' is " + type_name(f.info.type) +
                           ", accessed as " + type_name(want));
  if (!f.allocated) throw std::logic_error("field '" + name + "' is declared but not allocated");
}
}  // namespace

double* FieldRegistry::f64(const std::string& name) {
  return const_cast<double*>(std::as_const(*this).f64(name));
}

const double* FieldRegistry::f64(const std::string& name) const {
  const Field& f = get(name);
  check_access(f, name, FieldType::Float64);
  return f.f.data();
}

std::int64_t* FieldRegistry::i64(const std::string& name) {
  return const_cast<std::int64_t*>(std::as_const(*this).i64(name));
}

const std::int64_t* FieldRegistry::i64(const std::string& name) const {
  const Field& f = get(name);
  check_access(f, name, FieldType::Int64);
  return f.i.data();
}

double* FieldRegistry::f64_if(const std::string& name) {
  return declared(name) ? f64(name) : nullptr;
}

const double* FieldRegistry::f64_if(const std::string& name) const {
  return declared(name) ? f64(name) : nullptr;
}

const FieldInfo& FieldRegistry::info(const std::string& name) const { return get(name).info; }

std::vector<std::string> FieldRegistry::names() const {
  std::vector<std::string> out;
  out.reserve(fields_.size());
  for (const auto& [name, f] : fields_) out.push_back(name);  // std::map: already sorted
  return out;
}

const std::vector<std::string>& FieldRegistry::declared_by(const std::string& name) const {
  return get(name).users;
}

void FieldRegistry::permute(std::span<const std::size_t> order) {
  if (order.size() != count_)
    throw std::logic_error("FieldRegistry::permute: order has " + std::to_string(order.size()) +
                           " entries for " + std::to_string(count_) + " particles");
  // A bad index would read out of bounds in every field; one O(n) pass is cheap by comparison.
  for (const std::size_t o : order)
    if (o >= count_)
      throw std::logic_error("FieldRegistry::permute: index " + std::to_string(o) +
                             " out of range for " + std::to_string(count_) + " particles");
  std::vector<double> scratch_f;
  std::vector<std::int64_t> scratch_i;
  for (auto& [name, f] : fields_) {
    if (!f.allocated) continue;
    if (f.info.type == FieldType::Float64)
      gather(f.f, scratch_f, order, f.info.components);
    else
      gather(f.i, scratch_i, order, f.info.components);
  }
}

std::size_t FieldRegistry::bytes() const {
  std::size_t total = 0;
  for (const auto& [name, f] : fields_)
    total += f.f.capacity() * sizeof(double) + f.i.capacity() * sizeof(std::int64_t);
  return total;
}

}  // namespace sphforge
