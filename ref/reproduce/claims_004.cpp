// Enhanced-epipolar SLAM (seed 004): its relative claims, against reports/epi-table1.md .. epi-table3.md.
#include "reproduce/claims_build.h"

namespace dynref::reproduce {
namespace {

const char* kEpiT3 = "epi-table3.md";
const char* kEpiAte = "ATE RMSE against the paper's systems";
const char* kEpiAbl = "Module ablation (paper Table 6)";

const char* kEpiModuleBWhy =
    "Measured in ref/dynamic/epi/README.md, 'Module B' (reports/epi-table3.md Table 6, seeds 1-3): the SIFT "
    "stand-in for the improved ZippyPoint (spec 004 E3) does not reproduce the paper's B: on the dynamic scenes B "
    "alone is worse than orb (walking_static 1.11 vs 0.50 m, crowd 0.66 vs 0.41 m: nothing rejects the walkers and "
    "MNN2's mutual matches follow them as readily), and B + C is worse than C (7.3 vs 4.1 cm, 6.1 vs 1.7 cm).";

void EpiKeypoints(ClaimList& l) {
  const char* t1 = "epi-table1.md";
  const char* h = "Keypoints per frame";
  const PaperRef zippy = PaperCell("004-table1.csv", "Extracting Points", "Improvements to Zippypoint");
  const PaperRef orb = PaperCell("004-table1.csv", "Extracting Points", "ORB");
  l.Add("Sec. 4.1, Table 1",
        "ORB extracts few points on a weak-texture image; the proposed front end extracts many more (228 vs 11): ORB "
        "on the enhanced image above ORB on the raw one (static_xyz --low-light)",
        ClaimKind::kGreater,
        {Op("ORB + A keypoints", Cell(t1, h, "static_xyz --low-light", "ORB + A"), zippy),
         Op("ORB raw keypoints", Cell(t1, h, "static_xyz --low-light", "ORB raw"), orb)});
  l.Add("Sec. 4.1, Table 1", "The same with the float-descriptor extractor: SIFT on the enhanced image above SIFT "
                             "on the raw one (static_xyz --low-light)",
        ClaimKind::kGreater,
        {Op("SIFT + A keypoints", Cell(t1, h, "static_xyz --low-light", "SIFT + A")),
         Op("SIFT raw keypoints", Cell(t1, h, "static_xyz --low-light", "SIFT raw"))});
  l.Add("Sec. 4.1, Table 1", "Enhancement raises the keypoint count in normal light too (static_xyz, ORB + A above "
                             "ORB raw)",
        ClaimKind::kGreater,
        {Op("ORB + A keypoints", Cell(t1, h, "static_xyz", "ORB + A")),
         Op("ORB raw keypoints", Cell(t1, h, "static_xyz", "ORB raw"))});
}

void EpiMatching(ClaimList& l) {
  const char* t2 = "epi-table2.md";
  const char* h = "Matching of frame pairs";
  for (const char* typ : {"Light change", "Rotational change", "Perspective change", "Motion blur",
                          "Low light (both frames dark)"})
    l.Add("Sec. 4.2, Table 2",
          std::string("MNN2 matching is more accurate than brute force (the paper: ZippyPoint + MNN2 83.10 / 91.63 / "
                      "80.95 / 58.66 % against ORB + BF 50.00 / 70.40 / 69.72 / 42.86 %); ") + typ,
          ClaimKind::kGreater,
          {Op("ORB + MNN2 precision %", Cell(t2, h, std::string(typ) + " | ORB + MNN2", "precision %")),
           Op("ORB + BF precision %", Cell(t2, h, std::string(typ) + " | ORB + BF", "precision %"))});
  l.Add("Sec. 4.2, Table 2", "MNN2 matching lowers the computational cost against brute force (0.245 vs 0.472 s "
                             "per pair, light change)",
        ClaimKind::kLess,
        {Op("ORB + MNN2 ms / pair", Cell(t2, h, "Light change | ORB + MNN2", "ms / pair")),
         Op("ORB + BF ms / pair", Cell(t2, h, "Light change | ORB + BF", "ms / pair"))});
}

void EpiAte(ClaimList& l) {
  struct Seq {
    std::string preset, csv, paper_row;
  };
  const std::vector<Seq> seqs = {{"sitting_halfsphere", "004-table4.csv", "s_ halfsphere"},
                                 {"sitting_static", "004-table4.csv", "s_static"},
                                 {"walking_halfsphere", "004-table4.csv", "w_halfsphere"},
                                 {"walking_rpy", "004-table4.csv", "w_rpy"},
                                 {"walking_static", "004-table4.csv", "w_static"},
                                 {"walking_xyz", "004-table4.csv", "w_xyz"},
                                 {"crowd", "004-table5.csv", "crowd"},
                                 {"person_tracking", "004-table5.csv", "person_tracking"},
                                 {"synchronous", "004-table5.csv", "synchronous"}};
  for (const Seq& s : seqs) {
    const std::string row = s.preset + " | normal light";
    l.Add(std::string("Sec. 4.3, Table ") + (s.csv == "004-table4.csv" ? "4" : "5"),
          "The proposed system has a lower ATE than ORB-SLAM3 on every sequence (" + s.paper_row + ")",
          ClaimKind::kLess,
          {Op("epi_ALL", Cell(kEpiT3, kEpiAte, row, "epi_ALL (A + B + C)"), PaperCell(s.csv, s.paper_row, "OURS")),
           Op("orb", Cell(kEpiT3, kEpiAte, row, "orb"), PaperCell(s.csv, s.paper_row, "ORB-SLAM3 [8]"))});
  }
}

ClaimOperand EpiModule(const std::string& preset, const std::string& column, const std::string& paper_row,
                       const std::string& paper_column) {
  return Op(column, Cell(kEpiT3, kEpiAbl, preset + " | normal light", column),
            PaperCell("004-table6.csv", paper_row, paper_column));
}

void EpiAblation(ClaimList& l) {
  const std::vector<std::pair<std::string, std::string>> seqs = {{"walking_static", "w_static"}, {"crowd", "crowd"}};
  for (const auto& [preset, row] : seqs) {
    std::vector<ClaimOperand> ops = {EpiModule(preset, "ALL (epi_ALL)", row, "ALL")};
    for (const auto& [col, paper] : std::vector<std::pair<std::string, std::string>>{
             {"None (orb)", "None"}, {"A (epi_A)", "A"}, {"B (epi_B)", "B"}, {"C (epi_C)", "C"},
             {"A + C (epi)", "A + C"}, {"B + C (epi_BC)", "B + C"}})
      ops.push_back(EpiModule(preset, col, row, paper));
    l.Add("Sec. 4.3, Table 6", "All three modules together give the lowest ATE of the ablation (" + row + ")",
          ClaimKind::kLowestOf, ops, preset == "crowd" ? kEpiModuleBWhy : "");
    l.Add("Sec. 4.3, Table 6", "Module A (enhancement) alone improves on the backbone (" + row + ")", ClaimKind::kLess,
          {EpiModule(preset, "A (epi_A)", row, "A"), EpiModule(preset, "None (orb)", row, "None")});
    l.Add("Sec. 4.3, Table 6", "Module B (features and matching) alone improves on the backbone (" + row + ")",
          ClaimKind::kLess, {EpiModule(preset, "B (epi_B)", row, "B"), EpiModule(preset, "None (orb)", row, "None")},
          kEpiModuleBWhy);
  }
  l.Add("Sec. 4.3, Table 6", "Module C (dynamic rejection) gives the largest single-module gain: C below None, A and "
                             "B (w_static)",
        ClaimKind::kLowestOf,
        {EpiModule("walking_static", "C (epi_C)", "w_static", "C"),
         EpiModule("walking_static", "None (orb)", "w_static", "None"),
         EpiModule("walking_static", "A (epi_A)", "w_static", "A"),
         EpiModule("walking_static", "B (epi_B)", "w_static", "B")});
  l.Add("Sec. 4.3, Table 6", "Adding A to C improves it: A + C below C (w_static)", ClaimKind::kLess,
        {EpiModule("walking_static", "A + C (epi)", "w_static", "A + C"),
         EpiModule("walking_static", "C (epi_C)", "w_static", "C")});
  l.Add("Sec. 4.3, Table 6", "Adding B to C improves it: B + C below C (w_static)", ClaimKind::kLess,
        {EpiModule("walking_static", "B + C (epi_BC)", "w_static", "B + C"),
         EpiModule("walking_static", "C (epi_C)", "w_static", "C")},
        kEpiModuleBWhy);
}

void EpiTiming(ClaimList& l) {
  const char* h = "Tracking time (paper Table 7)";
  Claim& all = l.Add("Sec. 4.5, Table 7", "Average tracking time 41.9-58.4 ms per frame (all modules; checked: at "
                                          "most 58.4 ms)",
                     ClaimKind::kAtMost,
                     {Op("epi_ALL tracking total ms", Cell(kEpiT3, h, "epi_ALL | normal light", "tracking total"))},
                     "Measured in ref/dynamic/epi/README.md, 'Module B': epi_ALL tracks in 112-114 ms per frame against "
                     "63-67 ms for epi (A + C); SIFT extraction on one CPU core is about 60 ms of the difference (the "
                     "paper's learned extractor runs on an RTX 4060 Ti).");
  SetThreshold(all, 58.4, "Table 7: 41.9-58.4 ms");
  Claim& ac = l.Add("Sec. 4.5, Table 7", "Average tracking time at most 58.4 ms per frame, here for A + C (epi)",
                    ClaimKind::kAtMost,
                    {Op("epi tracking total ms", Cell(kEpiT3, h, "epi | normal light", "tracking total"))},
                    "Measured in reports/epi-table3.md, 'Tracking time (paper Table 7)', epi, normal light: Module A's "
                    "enhancement (epi.enhance) takes 35.2 of the 63.2 ms per frame on one CPU core.");
  SetThreshold(ac, 58.4, "Table 7: 41.9-58.4 ms");
  l.NotMeasured("Sec. 4.5, Table 7", "The system tracks faster than DS-SLAM (> 65 ms), DM-SLAM (> 201 ms) and "
                                     "DynaSLAM (> 300 ms)",
                "The peer systems are not run by dynref; their times are the paper's, on other GPUs.");
}

}  // namespace

std::vector<Claim> Claims004() {
  ClaimList l("004");
  EpiKeypoints(l);
  EpiMatching(l);
  EpiAte(l);
  EpiAblation(l);
  EpiTiming(l);
  return l.Take();
}

}  // namespace dynref::reproduce
