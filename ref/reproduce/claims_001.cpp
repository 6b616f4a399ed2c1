// SGDO-SLAM (seed 001): its relative claims, against reports/sgdo-table1.md .. sgdo-table7.md.
#include "reproduce/claims_build.h"

namespace dynref::reproduce {
namespace {

struct SgdoSeq {
  std::string preset;     // "walking_xyz" (Tables 1-3 rows)
  std::string t1_paper;   // "fr3_walking_xyz" (001-table1..3.csv)
  std::string t6_paper;   // "fr3_w_xyz" (001-table6.csv)
};

const std::vector<SgdoSeq>& SgdoWalking() {
  static const std::vector<SgdoSeq> seqs = {{"walking_xyz", "fr3_walking_xyz", "fr3_w_xyz"},
                                            {"walking_static", "fr3_walking_static", "fr3_w_static"},
                                            {"walking_rpy", "fr3_walking_rpy", "fr3_w_rpy"},
                                            {"walking_halfsphere", "fr3_walking_half", "fr3_w_half"}};
  return seqs;
}

const SgdoSeq kSgdoSitting = {"sitting_static", "fr3_sitting_static", "fr3_s_static"};

const char* kSgdoSittingWhy =
    "Measured in ref/dynamic/sgdo/README.md, 'Over seeds (issue 21)', sitting_static (same runs as "
    "reports/sgdo-table6.md): orb is already at 8.3 mm there (the paper's ORB-SLAM2: 10.6 mm), and the whole "
    "seated person is 'moving' in gt/moving.txt while only arms and head move; against the per-pixel moving "
    "parts (S+G+D+O) rejects 23 % of the moving keypoints with 47 % precision, and (S) alone is the best "
    "variant (5.7 mm).";

// The improvement column of an sgdo-table1..3 report (per seed, then mean ± S.D.).
ClaimOperand SgdoImprovement(const std::string& report, const std::string& heading, const std::string& preset) {
  return Op("improvement %", Cell(report, heading, preset, "Improvement RMSE (%)"));
}

void SgdoTables123(ClaimList& l) {
  for (const SgdoSeq& s : SgdoWalking()) {
    Claim& c = l.Add("Abstract, Sec. 5, Table 1",
                     "SGDO-SLAM improves the ATE by 95 % in highly dynamic TUM sequences compared to ORB-SLAM2 (" +
                         s.t1_paper + ")",
                     ClaimKind::kAtLeast, {SgdoImprovement("sgdo-table1.md", "Table 1: ATE (m)", s.preset)});
    SetThreshold(c, 95.0, "Abstract: 95 %");
  }
  Claim& sit = l.Add("Sec. 4.1.1, Table 1", "On fr3_sitting_static SGDO-SLAM cuts ORB-SLAM2's ATE RMSE by 44.34 %",
                     ClaimKind::kAtLeast, {SgdoImprovement("sgdo-table1.md", "Table 1: ATE (m)", "sitting_static")},
                     kSgdoSittingWhy);
  sit.threshold_paper = PaperCell("001-table1.csv", kSgdoSitting.t1_paper, "Improvement RMSE (%)");
  const std::vector<std::pair<std::string, std::string>> rpe = {
      {"sgdo-table2.md", "Table 2: translational RPE (m/s)"}, {"sgdo-table3.md", "Table 3: rotational RPE (deg/s)"}};
  const std::vector<std::string> csv = {"001-table2.csv", "001-table3.csv"};
  for (size_t t = 0; t < rpe.size(); ++t) {
    Claim& c = l.Add("Sec. 4.1.1, Table " + std::to_string(t + 2),
                     "The precision of SGDO-SLAM is improved over ORB-SLAM2 on every sequence, sitting_static included "
                     "(RPE RMSE cut > 0; the paper: " + std::string(t == 0 ? "43.24" : "27.46") + " %)",
                     ClaimKind::kAtLeast, {SgdoImprovement(rpe[t].first, rpe[t].second, "sitting_static")},
                     std::string(kSgdoSittingWhy) + " (Measured for the ATE; the RPE cells come from the same runs.)");
    SetThreshold(c, 0.0, "Sec. 4.1: improved on every sequence");
    Claim& r = l.Add("Sec. 4.1.1, Table " + std::to_string(t + 2),
                     "On fr3_walking_rpy SGDO-SLAM cuts ORB-SLAM2's RPE RMSE by the paper's printed improvement",
                     ClaimKind::kAtLeast, {SgdoImprovement(rpe[t].first, rpe[t].second, "walking_rpy")});
    r.threshold_paper = PaperCell(csv[t], "fr3_walking_rpy", "Improvement RMSE (%)");
  }
}

const char* kSgdoT6 = "sgdo-table6.md";
const char* kSgdoAte6 = "ATE RMSE (m): dynref on synthetic data";

ClaimOperand SgdoVariant(const SgdoSeq& s, const std::string& variant) {
  return Op(variant, Cell(kSgdoT6, kSgdoAte6, s.preset + " (dynref)", variant),
            PaperCell("001-table6.csv", s.t6_paper, "SGDO-SLAM " + variant + " RMSE"));
}

void SgdoTable6(ClaimList& l) {
  std::vector<SgdoSeq> all = SgdoWalking();
  all.push_back(kSgdoSitting);
  for (const SgdoSeq& s : all) {
    std::vector<ClaimOperand> ops = {SgdoVariant(s, "(S+G+D+O)")};
    for (const char* v : {"(G)", "(O)", "(S+G)", "(S+G+O)", "(S+G+D)"}) ops.push_back(SgdoVariant(s, v));
    l.Add("Sec. 4.3, Table 6",
          "(S+G+D+O) has the lowest ATE RMSE of the six ablation variants on every sequence (" + s.t6_paper + ")",
          ClaimKind::kLowestOf, ops, s.preset == "sitting_static" ? kSgdoSittingWhy : "");
  }
  for (const SgdoSeq& s : SgdoWalking())
    l.Add("Sec. 4.3, Table 6",
          "The back-end static point weights further suppress noise: (S+G+D+O) below (S+G+D) (" + s.t6_paper + ")",
          ClaimKind::kLess, {SgdoVariant(s, "(S+G+D+O)"), SgdoVariant(s, "(S+G+D)")});
  for (const SgdoSeq& s : {SgdoWalking()[0], SgdoWalking()[2]})
    l.Add("Sec. 4.3, Table 6",
          "Instance segmentation separates dynamic and static regions and reduces mismatches: (S+G) below (G) (" +
              s.t6_paper + ")",
          ClaimKind::kLess, {SgdoVariant(s, "(S+G)"), SgdoVariant(s, "(G)")});
}

void SgdoTimingAndPeers(ClaimList& l) {
  l.Add("Sec. 4.4, Table 7",
        "SGDO-SLAM incurs only a marginal per-frame latency increase (< 10 ms) over ORB-SLAM2 (38.81 vs 31.21 ms); "
        "checked here: the order ORB-SLAM2 < SGDO-SLAM",
        ClaimKind::kLess,
        {Op("ORB-SLAM2 SLAM ms", Cell("sgdo-table7.md", "Per module, ms per frame", "SLAM", "ORB-SLAM2"),
            PaperCell("001-table7.csv", "ORB-SLAM2", "Average Processing Time per Frame (ms)")),
         Op("SGDO-SLAM SLAM ms", Cell("sgdo-table7.md", "Per module, ms per frame", "SLAM", "SGDO-SLAM"),
            PaperCell("001-table7.csv", "SGDO-SLAM(ours)", "Average Processing Time per Frame (ms)"))});
  l.NotMeasured("Sec. 4.1.2, Table 4",
                "Compared with SG-SLAM, SGDO-SLAM has improved accuracy and robustness in all sequences",
                "The peer systems of Table 4 are not run by dynref (reports/sgdo-table4.md prints the paper's "
                "values beside ours).");
  l.NotMeasured("Sec. 4.2, Table 5",
                "On the two Bonn synchronous sequences SGDO-SLAM improves SG-SLAM's localisation accuracy by 97 %",
                "Table 5 (Bonn) has no dynref report and SG-SLAM is not run by dynref.");
}

}  // namespace

std::vector<Claim> Claims001() {
  ClaimList l("001");
  SgdoTables123(l);
  SgdoTable6(l);
  SgdoTimingAndPeers(l);
  return l.Take();
}

}  // namespace dynref::reproduce
