// The four verdicts of a checked claim (reports/claim_verdicts.h, docs/reports.md "Claims") on the
// synthetic runs of report_test_support.h: confirmed, partly, refuted and not measured for `better` and
// `same`, their evidence and details, and the counts in the report's and the study summary's lines.
// (`best` and `linear`: test_report.cpp.)
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "reports/claim_verdicts.h"
#include "reports/report.h"
#include "reports/summary.h"
#include "tests/report_test_support.h"

namespace causticbench {
namespace {

using nlohmann::json;
using namespace report_testing;

// The synthetic runs' relmse: photon_map k=50 0.1, 0.0123, 0.005 (1e4, 1e5, 1e6 photons), k=10 0.05;
// pinhole 0.03 (100 samples), 0.04 (400), 1600 failed.
json verdict_claims() {
  auto better = [](const std::string& text, const std::string& run, const std::string& than) {
    return json{{"text", text}, {"kind", "better"}, {"metric", "relmse"}, {"run", run}, {"than", than}};
  };
  auto same = [](const std::string& text, const std::string& run, const std::string& than, const json& tolerance) {
    json claim = {{"text", text}, {"kind", "same"}, {"metric", "relmse"}, {"run", run}, {"than", than}};
    claim.update(tolerance);
    return claim;
  };
  return json::array({
      // 0.005 beats 0.03 and 0.04: 2 of 2 pairs.
      better("better, all pairs", "photons=1000000,k=50", "method=pinhole"),
      // 0.1 beats neither pinhole run, 0.0123 and 0.005 beat both: 4 of 6 pairs.
      better("better, some pairs", "method=photon_map,k=50", "method=pinhole"),
      // 0.03 and 0.04 beat no 0.005: 0 of 2.
      better("better, no pair", "method=pinhole", "photons=1000000,k=50"),
      // |0.03 - 0.04| = 0.01 <= 0.3 x 0.04 = 0.012.
      same("same, relative", "samples=100", "samples=400", {{"relative_tolerance", 0.3}}),
      // 0.01 > 0.2 x 0.04 = 0.008.
      same("same, too strict", "samples=100", "samples=400", {{"relative_tolerance", 0.2}}),
      // against 0.05 (k=10): 0.04 is 0.01 away (within 0.015), 0.03 is 0.02 away (beyond): 1 of 2.
      same("same, some pairs", "method=pinhole", "method=photon_map,k=10", {{"absolute_tolerance", 0.015}}),
      // Either tolerance suffices: 0.01 > 0.2 x 0.04 but <= 0.011.
      same("same, either tolerance", "samples=100", "samples=400",
           {{"relative_tolerance", 0.2}, {"absolute_tolerance", 0.011}}),
      // Only the failed run matches `run`.
      same("same, nothing to compare", "samples=1600", "samples=400", {{"relative_tolerance", 0.5}}),
  });
}

class ClaimVerdictTest : public ReportTest {
 protected:
  void SetUp() override {
    ReportTest::SetUp();
    json experiment = json::parse(read_text(folder / "experiment.json"));
    experiment["claims"] = verdict_claims();
    write_json(folder / "experiment.json", experiment);
  }
};

TEST_F(ClaimVerdictTest, BetterAndSameAreConfirmedPartlyRefutedOrNotMeasured) {
  ReportSummary summary = write_report(folder.string());
  const json results = json::parse(read_text(summary.json));
  const json& claims = results.at("claims");
  ASSERT_EQ(claims.size(), 8u);
  std::vector<std::string> verdicts;
  for (const json& claim : claims) verdicts.push_back(claim.at("verdict"));
  EXPECT_EQ(verdicts, (std::vector<std::string>{"confirmed", "partly", "refuted", "confirmed", "refuted", "partly",
                                                "confirmed", "not measured"}));

  EXPECT_EQ(claims[0]["details"]["pairs"], 2);
  EXPECT_EQ(claims[0]["details"]["pairs_better"], 2);
  EXPECT_EQ(claims[1]["details"]["pairs"], 6);
  EXPECT_EQ(claims[1]["details"]["pairs_better"], 4);
  EXPECT_NE(claims[1]["evidence"].get<std::string>().find("Better in 4 of 6 pairs."), std::string::npos)
      << claims[1]["evidence"];
  EXPECT_EQ(claims[2]["details"]["pairs_better"], 0);

  const json& relative = claims[3]["details"];
  EXPECT_EQ(relative["pairs_within"], 1);
  EXPECT_EQ(relative["relative_tolerance"], 0.3);
  EXPECT_EQ(relative["absolute_tolerance"], 0.0);
  EXPECT_EQ(relative["deciding_run"]["key"], "pin_100");
  EXPECT_EQ(relative["deciding_than"]["key"], "pin_400");
  EXPECT_EQ(claims[3]["evidence"],
            "1 run matching samples=100 against 1 run matching samples=400: 1 of 1 pair is within 0.3 relative; "
            "nearest its edge: pinhole (filtering=none, samples=100) (relmse 0.03) against pinhole (filtering=none, "
            "samples=400) (relmse 0.04), "
            "difference relmse 0.01 (0.25 relative).");
  // The pair farthest beyond the tolerance decides: 0.03 against 0.05.
  const json& some = claims[5]["details"];
  EXPECT_EQ(some["pairs"], 2);
  EXPECT_EQ(some["pairs_within"], 1);
  EXPECT_EQ(some["deciding_run"]["key"], "pin_100");
  EXPECT_EQ(some["deciding_than"]["key"], "pm_1e5_k10");
  EXPECT_NE(claims[5]["evidence"].get<std::string>().find("1 of 2 pairs are within 0.015 absolute; farthest beyond it"),
            std::string::npos)
      << claims[5]["evidence"];
  EXPECT_NE(claims[6]["evidence"].get<std::string>().find("within 0.2 relative or 0.011 absolute"), std::string::npos)
      << claims[6]["evidence"];
  EXPECT_NE(claims[7]["evidence"].get<std::string>().find("(1 failed run not counted)"), std::string::npos)
      << claims[7]["evidence"];

  // The counts: one list of verdicts for the report's summary line, its badges and the study summary.
  EXPECT_EQ(summary.claims.total, 8u);
  EXPECT_EQ(summary.claims.of(Verdict::confirmed), 3u);
  EXPECT_EQ(summary.claims.of(Verdict::partly), 2u);
  EXPECT_EQ(summary.claims.of(Verdict::refuted), 2u);
  EXPECT_EQ(summary.claims.of(Verdict::not_measured), 1u);
  const std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("- 3 of 8 claims confirmed (2 partly, 2 refuted, 1 not measured)."), std::string::npos) << md;
  EXPECT_NE(md.find("| better, some pairs | partly |"), std::string::npos) << md;
  EXPECT_EQ(md.find("not confirmed"), std::string::npos) << "the old word for refuted";
  const std::string page = read_text(summary.html);
  EXPECT_EQ(count(page, "<span class=\"badge partly\">partly</span>"), 2u);
  EXPECT_EQ(count(page, "<span class=\"badge refuted\">refuted</span>"), 2u);
  EXPECT_EQ(page.find("not confirmed"), std::string::npos);

  SummaryFiles study = write_summary({folder.string()}, (root / "summary").string());
  EXPECT_EQ(study.claims.of(Verdict::partly), 2u);
  const std::string study_md = read_text(study.markdown);
  EXPECT_NE(study_md.find("8 claims: 3 confirmed, 2 partly, 2 refuted, 1 not measured."), std::string::npos)
      << study_md;
  EXPECT_NE(study_md.find("| better, some pairs | partly |"), std::string::npos) << study_md;
  EXPECT_EQ(study_md.find("not confirmed"), std::string::npos);
}

TEST(ClaimVerdicts, CountsFromThePairsOrGroupsThatHold) {
  EXPECT_EQ(verdict_of_count(0, 0), Verdict::not_measured);
  EXPECT_EQ(verdict_of_count(3, 3), Verdict::confirmed);
  EXPECT_EQ(verdict_of_count(1, 3), Verdict::partly);
  EXPECT_EQ(verdict_of_count(0, 3), Verdict::refuted);
  std::vector<std::string> names;
  for (Verdict verdict : kVerdicts) names.push_back(verdict_name(verdict));
  EXPECT_EQ(names, (std::vector<std::string>{"confirmed", "partly", "refuted", "not separated", "not measured"}));
  EXPECT_STREQ(verdict_badge(Verdict::not_measured), "unmeasured");
  EXPECT_STREQ(verdict_badge(Verdict::not_separated), "unseparated");
  // With intervals: separated pairs decide; none separated at all is a verdict of its own.
  EXPECT_EQ(verdict_of_separated_count(0, 0, 0), Verdict::not_measured);
  EXPECT_EQ(verdict_of_separated_count(3, 0, 3), Verdict::confirmed);
  EXPECT_EQ(verdict_of_separated_count(1, 0, 3), Verdict::partly);
  EXPECT_EQ(verdict_of_separated_count(1, 1, 3), Verdict::partly);
  EXPECT_EQ(verdict_of_separated_count(0, 1, 3), Verdict::refuted);
  EXPECT_EQ(verdict_of_separated_count(0, 0, 3), Verdict::not_separated);

  ClaimCounts counts;
  EXPECT_EQ(counts.breakdown(), "0 confirmed, 0 partly, 0 refuted, 0 not measured");
  counts.add(Verdict::confirmed);
  EXPECT_EQ(counts.sentence(), "1 of 1 claim confirmed.");
  counts.add(Verdict::partly);
  counts.add(Verdict::refuted);
  EXPECT_EQ(counts.sentence(), "1 of 3 claims confirmed (1 partly, 1 refuted).");
  // "not separated" only where some claim has it.
  EXPECT_EQ(counts.breakdown(), "1 confirmed, 1 partly, 1 refuted, 0 not measured");
  counts.add(Verdict::not_separated);
  EXPECT_EQ(counts.breakdown(), "1 confirmed, 1 partly, 1 refuted, 1 not separated, 0 not measured");
  EXPECT_EQ(counts.sentence(), "1 of 4 claims confirmed (1 partly, 1 refuted, 1 not separated).");
}

}  // namespace
}  // namespace causticbench
