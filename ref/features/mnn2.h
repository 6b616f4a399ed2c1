// "MNN2" matching of seed 004 (Sec. 3.2, spec 004 step 3, Eq. (4)-(7) reconstructed), for float
// and binary descriptors:
//   dist[i][j] = sum_k (D0[i,k] - D1[j,k])^2   (float rows L2-normalised first; binary rows:
//                Hamming distance h, which for +-1 coding is sum_k (a_k - b_k)^2 / 4, so the
//                ratio test is the same and tau is given in bits);
//   i -> j1 (nearest), j2 (second): accept when dist[i][j1] < rho * dist[i][j2] and dist[i][j1] < tau;
//   mutual: keep (i, j1) only when i is also the nearest of j1 among D0 (reverse NN).
// Brute force in index order; ties keep the lower index (deterministic).
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace dynref::features {

struct Mnn2Options {
  double ratio = 0.95;            // rho, paper Sec. 4.2
  double tau_float = 1.5625;      // squared L2 on unit rows; Hamming-equivalent of 100 / 256 bits (spec 004 (c))
  int tau_bits = 100;             // binary: ORB-SLAM TH_HIGH
  bool ratio_test = true;
  bool mutual = true;
};

// The backbone's use of MNN2 (backbone keys mnn2_matching, mnn2_ratio): when enabled it replaces
// ORB-SLAM2's brute-force rule (nearest <= TH_LOW, ratio, first come) in keyframe-to-frame
// matching (tracking/matcher.h SearchByBruteForce) and in the triangulation search of local
// mapping, with gate tau = the profile's TH_HIGH equivalent (spec 004 (c)).
struct BackboneMnn2 {
  bool enabled = false;
  double ratio = 0.95;  // rho, paper Sec. 4.2
};

struct DescriptorMatch {
  int i = 0, j = 0;      // query row in D0, train row in D1
  double distance = 0;   // squared L2 (float) or Hamming bits (binary)
  double second = 0;     // second-nearest distance (+inf when D1 has one row)
};

// D0, D1: CV_32F (float) or CV_8U (binary, one bit string per row); same type and width.
std::vector<DescriptorMatch> MatchMnn2(const cv::Mat& D0, const cv::Mat& D1, const Mnn2Options& o);
// CV_64F matrix of RowDistance (descriptor.h) between rows `rows` of A and rows `cols` of B: the
// candidates a backbone matcher allows, in their units (Hamming bits or squared L2 of unit rows).
cv::Mat DistanceMatrix(const cv::Mat& A, const std::vector<int>& rows, const cv::Mat& B, const std::vector<int>& cols);
// The MNN2 rules on a precomputed CV_64F distance matrix (rows: D0, columns: D1) with gate tau;
// the backbone's matchers use it on the candidates they allow (tracking/matcher.h).
std::vector<DescriptorMatch> SelectMnn2(const cv::Mat& distances, double tau, const Mnn2Options& o);

// What the MNN2 rule decided for one row (the trace of rejected candidates, ref/trace/README.md
// "Backbone MNN2 matches"): the tests in the order SelectMnn2 applies them, the first that fails.
enum class Mnn2Outcome { kAccepted = 0, kTau = 1, kRatio = 2, kNotMutual = 3 };
struct Mnn2Candidate {
  DescriptorMatch match;       // i, j = nearest column j1, distance = d(i, j1), second = d(i, j2)
  int second_j = -1;           // j2 (-1 when D1 has one column)
  int reverse_i = -1;          // nearest row of column j1 (the mutual check: accepted needs == i)
  double reverse_distance = 0; // d(reverse_i, j1)
  Mnn2Outcome outcome = Mnn2Outcome::kAccepted;
};
// Every row with a nearest column, accepted or not (SelectMnn2 = the accepted ones, same order).
std::vector<Mnn2Candidate> SelectMnn2Candidates(const cv::Mat& distances, double tau, const Mnn2Options& o);
// Plain nearest neighbour ("BF" in Table 2): every row of D0 to its nearest row of D1, no test.
std::vector<DescriptorMatch> MatchNearest(const cv::Mat& D0, const cv::Mat& D1);

}  // namespace dynref::features
