#include "reports/study_parts.h"

#include <cmath>
#include <limits>
#include <utility>

#include "modeling/errors.h"

namespace flexure::reports {
namespace {

using optimize::RecordKind;
using optimize::Refinement;

// One results.json object being read: each accessor names `where.key` in its InputError.
struct Fields {
  const nlohmann::json& j;
  std::string where;

  const nlohmann::json& at(const char* key) const {
    if (!j.is_object() || !j.contains(key)) throw InputError(where + ": no \"" + key + "\"");
    return j[key];
  }
  [[noreturn]] void wrong(const char* key, const char* expected) const {
    throw InputError(where + "." + key + ": expected " + expected);
  }
  // A number; null is a non-finite one (nlohmann writes NaN and ±∞ as null).
  double number(const char* key) const {
    const nlohmann::json& v = at(key);
    if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!v.is_number()) wrong(key, "a number");
    return v.get<double>();
  }
  std::optional<double> optionalNumber(const char* key) const {
    if (at(key).is_null()) return std::nullopt;
    return number(key);
  }
  int integer(const char* key) const {
    if (!at(key).is_number_integer()) wrong(key, "an integer");
    return at(key).get<int>();
  }
  std::string text(const char* key) const {
    if (!at(key).is_string()) wrong(key, "a string");
    return at(key).get<std::string>();
  }
  std::vector<double> numbers(const char* key) const {
    if (!at(key).is_array()) wrong(key, "an array of numbers");
    std::vector<double> values;
    for (const nlohmann::json& v : at(key)) {
      if (!v.is_null() && !v.is_number()) wrong(key, "an array of numbers");
      values.push_back(v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>());
    }
    return values;
  }
  std::vector<int> integers(const char* key) const {
    if (!at(key).is_array()) wrong(key, "an array of integers");
    std::vector<int> values;
    for (const nlohmann::json& v : at(key)) {
      if (!v.is_number_integer()) wrong(key, "an array of integers");
      values.push_back(v.get<int>());
    }
    return values;
  }
  std::optional<std::uint64_t> seed() const {
    if (at("seed").is_null()) return std::nullopt;
    if (!at("seed").is_number_unsigned()) wrong("seed", "null or a whole number");
    return at("seed").get<std::uint64_t>();
  }
  Refinement refinement(const char* key) const {
    const std::string name = text(key);
    for (Refinement r : {Refinement::Converges, Refinement::DoesNotConverge, Refinement::Exact,
                         Refinement::Unmeasured})
      if (optimize::refinementName(r) == name) return r;
    wrong(key, "a refinement verdict");
  }
  int energy(const optimize::StudyOptions& options) const {
    const std::string label = text("energy");
    for (size_t e = 0; e < options.energies.size(); ++e)
      if (options.energies[e].label == label) return static_cast<int>(e);
    throw InputError(where + ".energy: '" + label + "' is not an energy of the study");
  }
};

// order, energy_order, verdict and energy_verdict: a refinement series' fit, written on the
// series and on each of its records.
void readFit(const Fields& f, std::optional<double>& order, std::optional<double>& energyOrder,
             Refinement& verdict, Refinement& energyVerdict) {
  order = f.optionalNumber("order");
  energyOrder = f.optionalNumber("energy_order");
  verdict = f.refinement("verdict");
  energyVerdict = f.refinement("energy_verdict");
}

RecordKind recordKind(const Fields& f) {
  const std::string name = f.text("kind");
  for (RecordKind k : {RecordKind::Quadratic, RecordKind::NonlinearC2, RecordKind::Refinement})
    if (optimize::recordKindName(k) == name) return k;
  f.wrong("kind", "quadratic, nonlinear_c2 or refinement");
}

// The inverse of study_outputs.cpp's recordJson.
optimize::StudyRecord recordFromJson(const Fields& f, const optimize::StudyOptions& options) {
  optimize::StudyRecord r;
  r.kind = recordKind(f);
  r.energy = f.energy(options);
  r.family = f.text("family");
  r.seed = f.seed();
  if (!f.at("n").is_null()) r.n = f.integer("n");
  r.level = f.integer("level");
  r.h = f.number("h");
  r.vertices = f.integer("vertices");
  r.freeVertices = f.integer("free_vertices");
  r.factorizations = f.integer("factorizations");
  switch (r.kind) {
    case RecordKind::Quadratic:
      r.data = f.text("quadratic");
      r.energyPerArea = f.optionalNumber("energy_per_area");
      r.density = f.optionalNumber("density");
      r.c1Error = f.optionalNumber("c1");
      r.c2Error = f.number("c2");
      break;
    case RecordKind::NonlinearC2:
      r.data = f.text("quadratic");
      r.nonlinear.amplitudes = f.numbers("amplitudes");
      r.nonlinear.errors = f.numbers("errors");
      r.nonlinear.order = f.optionalNumber("order");
      if (!f.at("converged").is_boolean()) f.wrong("converged", "true or false");
      r.nonlinear.converged = f.at("converged").get<bool>();
      r.nonlinear.factorizations = r.factorizations;
      break;
    case RecordKind::Refinement:
      r.data = f.text("solution");
      r.solutionError = f.number("error");
      r.discreteEnergy = f.number("discrete_energy");
      r.exactEnergy = f.number("exact_energy");
      r.energyError = f.number("energy_error");
      readFit(f, r.order, r.energyOrder, r.verdict, r.energyVerdict);
      break;
  }
  return r;
}

optimize::RefinementFit fitFromJson(const Fields& f, const optimize::StudyOptions& options) {
  optimize::RefinementFit fit;
  fit.energy = f.energy(options);
  fit.family = f.text("family");
  fit.seed = f.seed();
  fit.n = f.integers("n");
  fit.h = f.numbers("h");
  fit.solutionErrors = f.numbers("errors");
  fit.energyErrors = f.numbers("energy_errors");
  readFit(f, fit.order, fit.energyOrder, fit.verdict, fit.energyVerdict);
  return fit;
}

}  // namespace

optimize::StudyResults studyResultsFromJson(const nlohmann::json& results,
                                            const optimize::StudyOptions& options,
                                            const std::string& where) {
  const Fields top{results, where};
  optimize::StudyResults study;
  for (const char* list : {"records", "refinement"})
    if (!top.at(list).is_array()) top.wrong(list, "an array");
  const nlohmann::json& records = top.at("records");
  for (size_t k = 0; k < records.size(); ++k) {
    const Fields record{records[k], where + ".records[" + std::to_string(k) + "]"};
    study.records.push_back(recordFromJson(record, options));
  }
  const nlohmann::json& fits = top.at("refinement");
  for (size_t k = 0; k < fits.size(); ++k) {
    const Fields fit{fits[k], where + ".refinement[" + std::to_string(k) + "]"};
    study.refinements.push_back(fitFromJson(fit, options));
  }
  return study;
}

optimize::StudyResults joinStudyParts(std::vector<optimize::StudyResults> parts) {
  optimize::StudyResults joined;
  for (size_t k = 0; k < parts.size(); ++k) {
    for (optimize::StudyRecord& r : parts[k].records) {
      r.energy = static_cast<int>(k);
      joined.records.push_back(std::move(r));
    }
    for (optimize::RefinementFit& f : parts[k].refinements) {
      f.energy = static_cast<int>(k);
      joined.refinements.push_back(std::move(f));
    }
  }
  return joined;
}

}  // namespace flexure::reports
