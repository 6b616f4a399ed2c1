#include "features/mnn2.h"

#include <opencv2/core/hal/hal.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "features/descriptor.h"

namespace dynref::features {
namespace {

// Pairwise distances, rows of a x rows of b.
cv::Mat Distances(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != b.type() || a.cols != b.cols) throw std::invalid_argument("MatchMnn2: descriptor types differ");
  cv::Mat d(a.rows, b.rows, CV_64F);
  if (a.type() == CV_8U) {
    for (int i = 0; i < a.rows; ++i)
      for (int j = 0; j < b.rows; ++j)
        d.at<double>(i, j) = cv::hal::normHamming(a.ptr<uchar>(i), b.ptr<uchar>(j), a.cols);
    return d;
  }
  if (a.type() != CV_32F) throw std::invalid_argument("MatchMnn2: descriptors must be CV_32F or CV_8U");
  cv::Mat na, nb;
  a.convertTo(na, CV_64F);
  b.convertTo(nb, CV_64F);
  for (cv::Mat* m : {&na, &nb})
    for (int r = 0; r < m->rows; ++r) {
      const double n = cv::norm(m->row(r));
      if (n > 0) m->row(r) /= n;
    }
  for (int i = 0; i < a.rows; ++i)
    for (int j = 0; j < b.rows; ++j) {
      const double* x = na.ptr<double>(i);
      const double* y = nb.ptr<double>(j);
      double s = 0;
      for (int k = 0; k < na.cols; ++k) s += (x[k] - y[k]) * (x[k] - y[k]);
      d.at<double>(i, j) = s;
    }
  return d;
}

}  // namespace

cv::Mat DistanceMatrix(const cv::Mat& A, const std::vector<int>& rows, const cv::Mat& B, const std::vector<int>& cols) {
  cv::Mat d(static_cast<int>(rows.size()), static_cast<int>(cols.size()), CV_64F);
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < cols.size(); ++c)
      d.at<double>(static_cast<int>(r), static_cast<int>(c)) = RowDistance(A, rows[r], B, cols[c]);
  return d;
}

std::vector<Mnn2Candidate> SelectMnn2Candidates(const cv::Mat& d, double tau, const Mnn2Options& o) {
  std::vector<Mnn2Candidate> out;
  if (d.empty()) return out;
  std::vector<int> reverse(size_t(d.cols), -1);  // nearest row of D0 for each column
  std::vector<double> reverse_d(size_t(d.cols), std::numeric_limits<double>::infinity());
  for (int j = 0; j < d.cols; ++j) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < d.rows; ++i)
      if (d.at<double>(i, j) < best) best = d.at<double>(i, j), reverse[size_t(j)] = i;
    reverse_d[size_t(j)] = best;
  }
  for (int i = 0; i < d.rows; ++i) {
    const double* r = d.ptr<double>(i);
    int j1 = -1, j2 = -1;
    double b1 = std::numeric_limits<double>::infinity(), b2 = b1;
    for (int j = 0; j < d.cols; ++j) {
      if (r[j] < b1) b2 = b1, j2 = j1, b1 = r[j], j1 = j;
      else if (r[j] < b2) b2 = r[j], j2 = j;
    }
    if (j1 < 0) continue;
    Mnn2Candidate c;
    c.match = {i, j1, b1, b2};
    c.second_j = j2;
    c.reverse_i = reverse[size_t(j1)];
    c.reverse_distance = reverse_d[size_t(j1)];
    if (!(b1 < tau)) c.outcome = Mnn2Outcome::kTau;
    else if (o.ratio_test && !(b1 < o.ratio * b2)) c.outcome = Mnn2Outcome::kRatio;
    else if (o.mutual && reverse[size_t(j1)] != i) c.outcome = Mnn2Outcome::kNotMutual;
    out.push_back(c);
  }
  return out;
}

std::vector<DescriptorMatch> SelectMnn2(const cv::Mat& d, double tau, const Mnn2Options& o) {
  std::vector<DescriptorMatch> out;
  for (const Mnn2Candidate& c : SelectMnn2Candidates(d, tau, o))
    if (c.outcome == Mnn2Outcome::kAccepted) out.push_back(c.match);
  return out;
}

std::vector<DescriptorMatch> MatchMnn2(const cv::Mat& D0, const cv::Mat& D1, const Mnn2Options& o) {
  if (D0.empty() || D1.empty()) return {};
  return SelectMnn2(Distances(D0, D1), D0.type() == CV_8U ? double(o.tau_bits) : o.tau_float, o);
}

std::vector<DescriptorMatch> MatchNearest(const cv::Mat& D0, const cv::Mat& D1) {
  Mnn2Options o;
  o.ratio_test = false, o.mutual = false;
  o.tau_float = std::numeric_limits<double>::infinity();
  o.tau_bits = std::numeric_limits<int>::max();
  return MatchMnn2(D0, D1, o);
}

}  // namespace dynref::features
