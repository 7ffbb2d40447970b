// A convergence study run in parts, one energy each, and joined back (reports/study_parts.h):
// the joined study's results.json, results.csv and summary.md equal the whole study's byte for
// byte; results.json read back names the field it cannot read; energy specs round-trip.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "modeling/errors.h"
#include "optimize/studies/convergence_study.h"
#include "reports/study_outputs.h"
#include "reports/study_parts.h"

namespace flexure {
namespace {

using modeling::MeshFamily;
using optimize::StudyOptions;
using optimize::StudyResults;

StudyOptions smallStudy(const std::vector<std::string>& energies) {
  StudyOptions o;
  o.energies.clear();
  for (const std::string& spec : energies) o.energies.push_back(optimize::parseEnergyVariant(spec));
  o.families = {MeshFamily::Patch48, MeshFamily::Delaunay};
  o.baseN = 4;
  o.levels = 2;
  o.amplitudes = 2;
  return o;
}

// results.json as a file holds it: dumped to text and parsed again.
nlohmann::json writtenAndRead(const StudyOptions& o, const StudyResults& r) {
  const std::string text = reports::studyResultsJson(o, r, optimize::summarizeStudy(o, r)).dump(1);
  return nlohmann::json::parse(text);
}

TEST(StudyParts, EveryEnergySpecReadsBackToItsVariant) {
  for (const char* spec : {"hinge", "hinge:tan", "triavg", "cotan", "cotan:barycentric", "midedge",
                           "midedge:free", "quadfit"}) {
    const optimize::EnergyVariant v = optimize::parseEnergyVariant(spec);
    const optimize::EnergyVariant back =
        optimize::parseEnergyVariant(optimize::energyVariantSpec(v));
    EXPECT_EQ(back.label, v.label) << spec;
    EXPECT_EQ(back.normals, v.normals) << spec;
    EXPECT_EQ(back.bending.hingeAngle, v.bending.hingeAngle) << spec;
    EXPECT_EQ(back.bending.vertexArea, v.bending.vertexArea) << spec;
  }
  for (const optimize::EnergyVariant& v : optimize::defaultEnergyVariants())
    EXPECT_EQ(optimize::parseEnergyVariant(optimize::energyVariantSpec(v)).label, v.label);
}

TEST(StudyParts, OneEnergyPartsJoinedEqualTheWholeStudyByteForByte) {
  const std::vector<std::string> energies = {"hinge", "midedge:free", "cotan"};
  const StudyOptions whole = smallStudy(energies);
  const StudyResults all = optimize::runConvergenceStudy(whole);
  std::vector<StudyResults> parts;
  for (const std::string& spec : energies) {
    const StudyOptions part = smallStudy({spec});
    parts.push_back(reports::studyResultsFromJson(
        writtenAndRead(part, optimize::runConvergenceStudy(part)), whole, spec));
  }
  const StudyResults joined = reports::joinStudyParts(parts);
  ASSERT_EQ(joined.records.size(), all.records.size());
  ASSERT_EQ(joined.refinements.size(), all.refinements.size());
  EXPECT_EQ(writtenAndRead(whole, joined).dump(1), writtenAndRead(whole, all).dump(1));
  EXPECT_EQ(reports::studyResultsCsv(whole, joined), reports::studyResultsCsv(whole, all));
  const auto summary = [&](const StudyResults& r) {
    return reports::studySummaryMarkdown(whole, r, optimize::summarizeStudy(whole, r));
  };
  EXPECT_EQ(summary(joined), summary(all));
  // Parts joined out of order are another study: the join keeps the order it is given.
  std::swap(parts[0], parts[2]);
  EXPECT_NE(reports::studyResultsCsv(whole, reports::joinStudyParts(parts)),
            reports::studyResultsCsv(whole, all));
}

TEST(StudyParts, ResultsJsonThatCannotBeReadNamesTheField) {
  const StudyOptions o = smallStudy({"hinge"});
  const nlohmann::json good = writtenAndRead(o, optimize::runConvergenceStudy(o));
  EXPECT_EQ(reports::studyResultsFromJson(good, o, "part").records.size(), good["records"].size());
  nlohmann::json noH = good;
  noH["records"][1].erase("h");
  EXPECT_THAT([&] { reports::studyResultsFromJson(noH, o, "part"); },
              testing::ThrowsMessage<InputError>(testing::HasSubstr("part.records[1]: no \"h\"")));
  nlohmann::json otherEnergy = good;
  otherEnergy["refinement"][0]["energy"] = "quadfit";
  EXPECT_THAT([&] { reports::studyResultsFromJson(otherEnergy, o, "part"); },
              testing::ThrowsMessage<InputError>(
                  testing::HasSubstr("part.refinement[0].energy: 'quadfit' is not an energy")));
  nlohmann::json badVerdict = good;
  badVerdict["refinement"][0]["verdict"] = "maybe";
  EXPECT_THAT([&] { reports::studyResultsFromJson(badVerdict, o, "part"); },
              testing::ThrowsMessage<InputError>(
                  testing::HasSubstr("part.refinement[0].verdict: expected a refinement verdict")));
}

}  // namespace
}  // namespace flexure
