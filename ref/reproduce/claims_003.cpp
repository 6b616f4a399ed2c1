// Motion-blur SLAM (seed 003): its relative claims, against reports/blur-table1.md and blur-table3.md.
#include "reproduce/claims_build.h"

namespace dynref::reproduce {
namespace {

struct BlurSeq {
  std::string preset;      // "walking_xyz"
  std::string report_row;  // "walking_xyz (fr3/w/xyz)"
  std::string paper_row;   // "fr3/w/xyz"
};

const std::vector<BlurSeq>& BlurWalking() {
  static const std::vector<BlurSeq> seqs = {{"walking_xyz", "walking_xyz (fr3/w/xyz)", "fr3/w/xyz"},
                                            {"walking_halfsphere", "walking_halfsphere (fr3/w/half)", "fr3/w/half"},
                                            {"walking_static", "walking_static (fr3/w/static)", "fr3/w/static"},
                                            {"walking_rpy", "walking_rpy (fr3/w/rpy)", "fr3/w/rpy"}};
  return seqs;
}
const BlurSeq kBlurSitting = {"sitting_static", "sitting_static (fr3/s/static)", "fr3/s/static"};

const char* kBlurT1 = "blur-table1.md";
const char* kBlurT3 = "blur-table3.md";
const char* kBlurTum = "ATE RMSE (m): TUM analogues";
const char* kBlurSeeds = "Per seed: ATE RMSE (m)";
const char* kBlurAbl = "Ablation: ATE RMSE (m) (paper Table 3)";

const char* kBlurDepthWhy =
    "Measured in ref/dynamic/blur/README.md, 'Measured' (reports/blur-table3.md, 'Compensation and depth fusion "
    "against the true person pixels'): depth fusion recovers 6-11 % of the person pixels the segmenter missed and "
    "91-98 % of what it adds is not a person (the human value range around the box's mean depth, spec 003 E6, "
    "follows the background inside the box).";

ClaimOperand BlurSeedCut(const std::string& preset, const std::string& variant) {
  return Op(variant, Cell(kBlurT1, kBlurSeeds, preset + " | " + variant, "seeds 1,2,3"));
}

void BlurTables12(ClaimList& l) {
  for (const BlurSeq& s : BlurWalking()) {
    Claim& c = l.Add("Sec. 4.2, Table 1",
                     "In high-dynamic sequences the method cuts ORB-SLAM2's ATE RMSE by 96.5 % on average (checked per "
                     "sequence: " + s.paper_row + ")",
                     ClaimKind::kImprovement, {BlurSeedCut(s.preset, "Ours (blur)"), BlurSeedCut(s.preset, "ORB-SLAM2")});
    SetThreshold(c, 96.5, "Sec. 4.2 text: 96.5 %");
  }
  Claim& half = l.Add("Sec. 4.2, Table 1", "On fr3/w/half (severe motion blur) RMSE is reduced by 94.5 % against ORBSLAM2",
                      ClaimKind::kImprovement,
                      {BlurSeedCut("walking_halfsphere", "Ours (blur)"), BlurSeedCut("walking_halfsphere", "ORB-SLAM2")});
  half.threshold_paper = PaperCell("003-table1.csv", "fr3/w/half", "Ours RMSE");
  half.threshold_paper_base = PaperCell("003-table1.csv", "fr3/w/half", "ORBSLAM2 RMSE");
  std::vector<BlurSeq> tum = BlurWalking();
  tum.push_back(kBlurSitting);
  for (const BlurSeq& s : tum)
    l.Add("Sec. 4.2, Table 1",
          "The method outperforms the baselines in ATE in both high- and low-dynamic environments (" + s.paper_row +
              "; dynref's baselines: orb and its sgdo)",
          ClaimKind::kLowestOf,
          {Op("blur", Cell(kBlurT1, kBlurTum, s.report_row, "Ours (blur)"), PaperCell("003-table1.csv", s.paper_row, "Ours RMSE")),
           Op("orb", Cell(kBlurT1, kBlurTum, s.report_row, "ORB-SLAM2"),
              PaperCell("003-table1.csv", s.paper_row, "ORBSLAM2 RMSE")),
           Op("sgdo", Cell(kBlurT1, kBlurTum, s.report_row, "SGDO-SLAM (dynref)"))});
  for (const char* preset : {"crowd", "person_tracking"}) {
    Claim& c = l.Add("Sec. 4.2, Table 2",
                     std::string("On Bonn the method cuts ORB-SLAM2's RMSE by 96.6 % on average (checked per "
                                 "sequence: ") + preset + ")",
                     ClaimKind::kImprovement, {BlurSeedCut(preset, "Ours (blur)"), BlurSeedCut(preset, "ORB-SLAM2")});
    SetThreshold(c, 96.6, "Sec. 4.2 text: 96.6 %");
  }
  l.NotMeasured("Sec. 4.2, Table 2", "On Bonn the method cuts SG-SLAM's RMSE by 24.8 % and its S.D. by 35.8 %",
                "SG-SLAM is not run by dynref.");
}

ClaimOperand BlurAblation(const BlurSeq& s, const std::string& variant) {
  return Op(variant, Cell(kBlurT3, kBlurAbl, s.report_row, variant),
            PaperCell("003-table3.csv", s.paper_row, variant + " RMSE"));
}

void BlurTable3(ClaimList& l) {
  for (const BlurSeq& s : BlurWalking())
    l.Add("Sec. 4.3, Table 3", "Missed-segmentation compensation improves the ATE (" + s.paper_row + ")",
          ClaimKind::kLess, {BlurAblation(s, "Ours"), BlurAblation(s, "w/o Compensation")});
  for (const BlurSeq& s : BlurWalking())
    l.Add("Sec. 4.3, Table 3",
          "Fusing depth with the masks helps in sequences with dramatic camera or human motion (" + s.paper_row + ")",
          ClaimKind::kLess, {BlurAblation(s, "Ours"), BlurAblation(s, "w/o Depth")},
          s.preset == "walking_xyz" || s.preset == "walking_halfsphere" ? kBlurDepthWhy : "");
  l.Add("Sec. 4.3, Table 3", "On fr3/s/static the best result is reached without depth fusion",
        ClaimKind::kLess, {BlurAblation(kBlurSitting, "w/o Depth"), BlurAblation(kBlurSitting, "Ours")});
  for (const BlurSeq& s : {BlurWalking()[3], BlurWalking()[1]})
    l.Add("Sec. 4.3, Table 3",
          "The probability-based detection enhances performance, particularly on fr3/w/rpy and fr3/w/half (" +
              s.paper_row + ")",
          ClaimKind::kLess, {BlurAblation(s, "Ours"), BlurAblation(s, "w/o Probability")});
}

void BlurSweepAndTiming(ClaimList& l) {
  const char* sweep = "Sweep of dilation_size";
  l.Add("Sec. 4.5, Fig. 12", "dilation_size = 10 is the optimal choice (walking_xyz, against 0, 5, 20, 30)",
        ClaimKind::kLowestOf,
        {Op("10 px", Cell(kBlurT3, sweep, "walking_xyz", "10")), Op("0 px", Cell(kBlurT3, sweep, "walking_xyz", "0")),
         Op("5 px", Cell(kBlurT3, sweep, "walking_xyz", "5")), Op("20 px", Cell(kBlurT3, sweep, "walking_xyz", "20")),
         Op("30 px", Cell(kBlurT3, sweep, "walking_xyz", "30"))});
  l.Add("Sec. 4.5, Fig. 12", "Oversized masks remove static points and degrade the system: 10 px below 30 px "
                             "(walking_xyz)",
        ClaimKind::kLess,
        {Op("10 px", Cell(kBlurT3, sweep, "walking_xyz", "10")), Op("30 px", Cell(kBlurT3, sweep, "walking_xyz", "30"))});
  l.Add("Sec. 4.5, Fig. 12", "Undersized masks let dynamic points in and degrade the system: 10 px below 0 px "
                             "(walking_xyz)",
        ClaimKind::kLess,
        {Op("10 px", Cell(kBlurT3, sweep, "walking_xyz", "10")), Op("0 px", Cell(kBlurT3, sweep, "walking_xyz", "0"))});
  const char* ms = "Per-module CPU ms per frame of the full method (paper Table 4)";
  l.Add("Sec. 4.6, Table 4",
        "fr3/w/half needs more loop closing and local mapping ('Others') than the other sequences (16.79 vs 8.58 ms "
        "on fr3/w/static)",
        ClaimKind::kGreater,
        {Op("Others ms, walking_halfsphere", Cell(kBlurT3, ms, "walking_halfsphere", "Others"),
            PaperCell("003-table4.csv", "fr3/w/half", "Others")),
         Op("Others ms, walking_static", Cell(kBlurT3, ms, "walking_static", "Others"),
            PaperCell("003-table4.csv", "fr3/w/static", "Others"))});
  Claim& c = l.Add("Sec. 4.6, Table 4", "The method fulfils real-time demands: total time per frame on fr3/w/half at "
                                        "most the paper's 47.49 ms",
                   ClaimKind::kAtMost, {Op("Total ms", Cell(kBlurT3, ms, "walking_halfsphere", "Total"))});
  c.threshold_paper = PaperCell("003-table4.csv", "fr3/w/half", "Total");
}

}  // namespace

std::vector<Claim> Claims003() {
  ClaimList l("003");
  BlurTables12(l);
  BlurTable3(l);
  BlurSweepAndTiming(l);
  return l.Take();
}

}  // namespace dynref::reproduce
