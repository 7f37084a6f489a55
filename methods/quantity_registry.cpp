// The quantity registry (declared in quantity_registry.h).
#include "methods/quantity_registry.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/errors.h"
#include "methods/registry.h"

namespace causticbench {

std::vector<QuantityInfo> quantity_registry() {
  std::vector<QuantityInfo> all = measured_quantities();
  for (const MethodEntry& entry : method_registry()) {
    for (const QuantityInfo& counter : entry.info().counters) {
      bool known = std::any_of(all.begin(), all.end(), [&](const QuantityInfo& q) { return q.name == counter.name; });
      if (!known) all.push_back(counter);
    }
  }
  return all;
}

std::vector<std::string> quantity_names() {
  std::vector<std::string> names;
  for (const QuantityInfo& quantity : quantity_registry()) names.push_back(quantity.name);
  return names;
}

// Looked up without assembling the registry: reports call this per run and quantity.
std::optional<QuantityInfo> find_quantity(const std::string& name) {
  for (const QuantityInfo& quantity : measured_quantities())
    if (quantity.name == name) return quantity;
  for (const MethodEntry& entry : method_registry())
    for (const QuantityInfo& counter : entry.info().counters)
      if (counter.name == name) return counter;
  return std::nullopt;
}

std::string expected_quantity_text(const std::string& name, bool ranked_only) {
  std::vector<std::string> names;
  for (const QuantityInfo& quantity : quantity_registry())
    if (!ranked_only || quantity.direction != QuantityDirection::none) names.push_back(quantity.name);
  return fmt::format("a quantity{}: one of {}{}", ranked_only ? " that is better one way" : "", join(names, ", "),
                     did_you_mean(name, names));
}

QuantityInfo require_quantity(const std::string& name, const std::string& context, bool ranked_only) {
  std::optional<QuantityInfo> quantity = find_quantity(name);
  if (!quantity || (ranked_only && quantity->direction == QuantityDirection::none)) {
    throw InputError(fmt::format("{}: '{}' is not {}", context, name, expected_quantity_text(name, ranked_only)));
  }
  return *quantity;
}

bool quantity_better(const std::string& name, double a, double b) {
  if (std::optional<QuantityInfo> quantity = find_quantity(name)) return quantity_better(*quantity, a, b);
  QuantityInfo cost;
  cost.direction = QuantityDirection::lower;
  return quantity_better(cost, a, b);
}

std::string direction_text(const std::string& name) {
  std::optional<QuantityInfo> quantity = find_quantity(name);
  return quantity ? direction_text(*quantity) : "lower is better";
}

std::string direction_arrow(const std::string& name) {
  std::optional<QuantityInfo> quantity = find_quantity(name);
  return quantity ? direction_arrow(*quantity) : "\u2193";
}

}  // namespace causticbench
