// MGD-SLAM (seed 000): its relative claims, against reports/mgd-table2.md and mgd-table4.md.
#include "reproduce/claims_build.h"

namespace dynref::reproduce {
namespace {

struct MgdSeq {
  std::string report_row;  // "walking_xyz (w_xyz)"
  std::string preset;      // "walking_xyz"
  std::string paper_row;   // "w_xyz"
};

const std::vector<MgdSeq>& MgdWalking() {
  static const std::vector<MgdSeq> seqs = {{"walking_halfsphere (w_half)", "walking_halfsphere", "w_half"},
                                           {"walking_rpy (w_rpy)", "walking_rpy", "w_rpy"},
                                           {"walking_static (w_static)", "walking_static", "w_static"},
                                           {"walking_xyz (w_xyz)", "walking_xyz", "w_xyz"}};
  return seqs;
}

const char* kMgdT2 = "mgd-table2.md";
const char* kMgdT4 = "mgd-table4.md";
const char* kMgdAte2 = "ATE RMSE (m) (paper Table 2)";
const char* kMgdAte4 = "ATE RMSE (m) (paper Table 4)";
const char* kMgdRpe = "RPE (paper Table 5)";
const char* kMgdSeeds = "Per seed: ATE RMSE (m)";
const char* kMgdOrbCol = "ORB-SLAM2 backbone (orb)";
const char* kMgdNdCol = "MGD-SLAM-nD (mgd-nd)";
const char* kMgdCol = "MGD-SLAM (mgd)";

// mgd lowest of orb, mgd-nd and mgd in `heading` of `report` (paper values from `csv`).
std::vector<ClaimOperand> MgdThree(const std::string& report, const std::string& heading, const MgdSeq& s,
                                   const std::string& csv) {
  return {Op("mgd", Cell(report, heading, s.report_row, kMgdCol), PaperCell(csv, s.paper_row, "MGD-SLAM")),
          Op("orb", Cell(report, heading, s.report_row, kMgdOrbCol), PaperCell(csv, s.paper_row, "ORB-SLAM3")),
          Op("mgd-nd", Cell(report, heading, s.report_row, kMgdNdCol),
             csv == "000-table2.csv" ? PaperRef{} : PaperCell(csv, s.paper_row, "MGD-SLAM-nD"))};
}

void MgdTable2(ClaimList& l) {
  for (const MgdSeq& s : MgdWalking())
    l.Add("Sec. 4.2, Table 2", "MGD-SLAM consistently achieves the lowest ATE across all w-type sequences (" +
                                   s.paper_row + ")",
          ClaimKind::kLowestOf, MgdThree(kMgdT2, kMgdAte2, s, "000-table2.csv"));
  l.Add("Sec. 4.2, Table 2",
        "In nearly static sequences such as s_static MGD-SLAM achieves the best or near-best performance",
        ClaimKind::kLowestOf,
        MgdThree(kMgdT2, kMgdAte2, {"sitting_static (s_static)", "sitting_static", "s_static"}, "000-table2.csv"));
  l.Add("Sec. 4.2, Table 2", "s_xyz (moderately dynamic): MGD-SLAM's ATE below ORB-SLAM3's (0.021 vs 0.031 m)",
        ClaimKind::kLess,
        {Op("mgd", Cell(kMgdT2, kMgdAte2, "sitting_xyz (s_xyz)", kMgdCol), PaperCell("000-table2.csv", "s_xyz", "MGD-SLAM")),
         Op("orb", Cell(kMgdT2, kMgdAte2, "sitting_xyz (s_xyz)", kMgdOrbCol),
            PaperCell("000-table2.csv", "s_xyz", "ORB-SLAM3"))});
}

void MgdTable4(ClaimList& l) {
  for (const MgdSeq& s : MgdWalking()) {
    Claim& c = l.Add("Sec. 4.3, Table 4",
                     "MGD-SLAM reduces the ATE RMSE by over 95 % compared with ORB-SLAM3 (" + s.paper_row + ")",
                     ClaimKind::kImprovement,
                     {Op("mgd", Cell(kMgdT4, kMgdSeeds, s.preset + " | " + kMgdCol, "seeds 1,2,3")),
                      Op("orb", Cell(kMgdT4, kMgdSeeds, s.preset + " | " + kMgdOrbCol, "seeds 1,2,3"))});
    SetThreshold(c, 95.0, "Sec. 4.3 text: over 95 %");
  }
  for (const MgdSeq& s : {MgdWalking()[0], MgdWalking()[3]}) {
    Claim& c = l.Add("Sec. 4.3, Table 4",
                     "Removing dynamic features cuts the ATE of MGD-SLAM-nD by nearly 90 %, particularly on w_half "
                     "and w_xyz (" + s.paper_row + ": the paper's own cut on this sequence)",
                     ClaimKind::kImprovement,
                     {Op("mgd", Cell(kMgdT4, kMgdSeeds, s.preset + " | " + kMgdCol, "seeds 1,2,3")),
                      Op("mgd-nd", Cell(kMgdT4, kMgdSeeds, s.preset + " | " + kMgdNdCol, "seeds 1,2,3"))});
    c.threshold_paper = PaperCell("000-table4.csv", s.paper_row, "MGD-SLAM");
    c.threshold_paper_base = PaperCell("000-table4.csv", s.paper_row, "MGD-SLAM-nD");
  }
  for (const MgdSeq& s : MgdWalking())
    l.Add("Sec. 4.3, Table 4",
          "Multi-granularity constraints alone improve on the point-only system: MGD-SLAM-nD's ATE below "
          "ORB-SLAM3's (average 0.197 vs 0.475 m; " + s.paper_row + ")",
          ClaimKind::kLess,
          {Op("mgd-nd", Cell(kMgdT4, kMgdAte4, s.report_row, kMgdNdCol), PaperCell("000-table4.csv", s.paper_row, "MGD-SLAM-nD")),
           Op("orb", Cell(kMgdT4, kMgdAte4, s.report_row, kMgdOrbCol), PaperCell("000-table4.csv", s.paper_row, "ORB-SLAM3"))});
}

void MgdTable5And6(ClaimList& l) {
  for (const MgdSeq& s : MgdWalking())
    l.Add("Sec. 4.3, Table 5",
          "The full MGD-SLAM consistently achieves the lowest RPE across all evaluated sequences (" + s.paper_row + ")",
          ClaimKind::kLowestOf, MgdThree(kMgdT4, kMgdRpe, s, "000-table5.csv"));
  const MgdSeq& rpy = MgdWalking()[1];
  l.Add("Sec. 4.3, Table 5",
        "MGD-SLAM-nD's RPE increases noticeably under rapid rotation: above ORB-SLAM3's on w_rpy (0.832 vs 0.641)",
        ClaimKind::kLess,
        {Op("orb", Cell(kMgdT4, kMgdRpe, rpy.report_row, kMgdOrbCol), PaperCell("000-table5.csv", "w_rpy", "ORB-SLAM3")),
         Op("mgd-nd", Cell(kMgdT4, kMgdRpe, rpy.report_row, kMgdNdCol), PaperCell("000-table5.csv", "w_rpy", "MGD-SLAM-nD"))});
  const char* module = "Per-module CPU ms per frame of MGD-SLAM (paper Table 6)";
  l.Add("Sec. 4.5, Table 6",
        "Dynamic feature removal is light (about 9 ms) next to multi-granularity feature extraction (about 31 ms); "
        "walking_xyz",
        ClaimKind::kLess,
        {Op("dynamic removal ms", Cell(kMgdT4, module, "walking_xyz", "dynamic removal"),
            PaperCell("000-table6.csv", "Dynamic feature removal", "Average Time (ms)")),
         Op("feature extraction ms", Cell(kMgdT4, module, "walking_xyz", "feature extraction"),
            PaperCell("000-table6.csv", "Multi-granularity feature extraction", "Average Time (ms)"))});
  Claim& c = l.Add("Sec. 4.5, Table 6",
                   "Average tracking time about 46 ms per frame (22 FPS, near real time); walking_xyz",
                   ClaimKind::kAtMost, {Op("tracking total ms", Cell(kMgdT4, module, "walking_xyz", "tracking total"))});
  c.threshold_paper = PaperCell("000-table6.csv", "Total tracking time", "Average Time (ms)");
}

void MgdCuesAndPeers(ClaimList& l) {
  l.Add("Sec. 3.4, Sec. 4.3",
        "Combining the short-term cue with geometric consistency across multiple frames (P_pro, P_mf; log-odds "
        "fusion) detects dynamic features better than the short-term cue alone: F1 of the dynamic points, all "
        "cues above only P_LS",
        ClaimKind::kGreater,
        {Op("all cues + diffusion F1 %", Cell(kMgdT2, "All sequences together", "all cues + diffusion", "F1#1")),
         Op("only P_LS F1 %", Cell(kMgdT2, "All sequences together", "only P_LS", "F1#1"))},
        "Measured in ref/dynamic/mgd/README.md, 'Over seeds', 'Which cue carries it' (same runs as "
        "reports/mgd-table2.md, made before issue 38's update order): P_pro is computable for few features (the "
        "map points of keyframes that covisible keyframes observe; 5-7 % recall alone) and contributes logit 0 "
        "elsewhere, so the fused score is mostly P_LS with P_mf at weight 0.2: P_LS alone F1 56.5 % vs fusion "
        "56.0 %.");
  l.NotMeasured("Sec. 4.2, Table 2",
                "MGD-SLAM's average ATE (0.023 m) is about 66 % below the best traditional baseline, Dynamic-VINS "
                "(0.068 m)",
                "Dynamic-VINS, DS-SLAM, SG-SLAM and DRG-SLAM are not run by dynref (their columns are the paper's).");
  l.NotMeasured("Sec. 4.2, Table 3", "MGD-SLAM outperforms the best neural SLAM method, DDN-SLAM, by about 5 %",
                "No neural SLAM system is run by dynref.");
  l.NotMeasured("Sec. 4.4, Figs. 8-11",
                "On THUD store-c1 and canteen-p1-c1 MGD-SLAM tracks longest of ORB-SLAM3, MWSLAM, MGD-SLAM-nD",
                "THUD is not synthesised or bundled; the claim is qualitative (trajectory length, map coherence).");
}

}  // namespace

std::vector<Claim> Claims000() {
  ClaimList l("000");
  MgdTable2(l);
  MgdTable4(l);
  MgdTable5And6(l);
  MgdCuesAndPeers(l);
  return l.Take();
}

}  // namespace dynref::reproduce
