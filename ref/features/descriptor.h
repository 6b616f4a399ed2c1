// Descriptor comparison shared by every matcher (issue 17, Module B): ORB's 256-bit strings and
// the float descriptors of SIFT / learned extractors go through the same functions, and a
// DescriptorProfile tells a matcher the units of its gates.
//   CV_8U rows: bit strings, distance = Hamming bits (ORBmatcher::DescriptorDistance);
//   CV_32F rows: L2-normalised by the extractor, distance = squared L2 in [0, 4], summed in index
//                order in float (deterministic). For +-1/sqrt(256) coded bits the two agree up to
//                squared L2 = 4 * Hamming / 256 (spec 004 step 3), which is how the float gates
//                of a profile relate to ORB-SLAM2's bit thresholds.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref::features {

// What the matchers need to know about an extractor's output.
struct DescriptorProfile {
  std::string extractor = "orb";  // orb | sift | onnx
  int type = CV_8U;               // CV_8U bits or CV_32F unit rows
  int cols = 32;                  // bytes (CV_8U) or floats (CV_32F) per row
  // A distance no match reaches: the matchers' initial "best" (ORBmatcher starts at 256).
  float worst = 256;
  // ORBmatcher TH_LOW (keyframe matching, triangulation, fusion), TH_HIGH (projection search)
  // and the relocalisation refinement threshold (Tracking::Relocalization, 64), in the units above.
  float th_low = 50, th_high = 100, th_reloc = 64;
  // Keypoint angles are meaningful: the matchers' rotation-consistency histogram is applied.
  bool oriented = true;
  // Scale pyramid the keypoint octaves index (ORB: 8 levels of 1.2).
  int n_levels = 8;
  double scale_factor = 1.2;
  void Check() const;  // InputError naming the bad field
};

// Hamming distance of two 32-byte descriptors (ORBmatcher::DescriptorDistance).
int DescriptorDistance(const uint8_t* a, const uint8_t* b);
inline int DescriptorDistance(const cv::Mat& a, const cv::Mat& b) {
  return DescriptorDistance(a.ptr<uint8_t>(0), b.ptr<uint8_t>(0));
}
// Hamming distance of two n-byte strings.
int HammingBits(const uint8_t* a, const uint8_t* b, int n_bytes);
// HammingBits without the POPCNT instruction (what a CPU without it runs), for tests.
int HammingBitsPortableForTest(const uint8_t* a, const uint8_t* b, int n_bytes);
// Squared L2 of two n-float rows, summed in index order.
float SquaredL2(const float* a, const float* b, int n);

// Distance of row i of A and row j of B (same type and width): Hamming bits or squared L2.
inline float RowDistance(const cv::Mat& A, int i, const cv::Mat& B, int j) {
  if (A.type() == CV_8U) {
    if (A.cols == 32) return static_cast<float>(DescriptorDistance(A.ptr<uint8_t>(i), B.ptr<uint8_t>(j)));
    return static_cast<float>(HammingBits(A.ptr<uint8_t>(i), B.ptr<uint8_t>(j), A.cols));
  }
  return SquaredL2(A.ptr<float>(i), B.ptr<float>(j), A.cols);
}

// Rows of a CV_32F matrix scaled to unit L2 norm (norm accumulated in double; zero rows stay zero).
void NormaliseRows(cv::Mat* descriptors);

// ORBmatcher thresholds.
constexpr int kThHigh = 100;
constexpr int kThLow = 50;
constexpr int kHistoLength = 30;

// ORBmatcher rotation histogram: bin of an angle difference. ORB-SLAM2 computes
// bin = round(rot * (1/HISTO_LENGTH)) with rot in degrees, i.e. 30-degree bins (only 12 of the
// 30 bins are used); reproduced as published.
int RotationBin(float angle1_deg, float angle2_deg);
// ORBmatcher::ComputeThreeMaxima: indices of the three fullest bins (-1 when a bin holds less
// than 10 % of the fullest).
void ComputeThreeMaxima(const std::vector<std::vector<int>>& histo, int* ind1, int* ind2, int* ind3);

}  // namespace dynref::features
