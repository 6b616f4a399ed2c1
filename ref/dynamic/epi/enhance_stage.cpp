// epi.enhance: seed 004 Module A on every frame's grey image (enhance.h), (alpha, p) tuned once by
// BOA on the first frame (butterfly.h, spec 004 E2) or fixed. Traced (README "Trace", p = 0): the
// BOA best fitness per iteration and the chosen (alpha, p); per frame I_lo, I_hi with the CDF
// values that prove them, the fitness with the statistics it is computed from, the mean grey
// before and after.
#include "core/error.h"
#include "dynamic/epi/enhance_terms.h"
#include "dynamic/epi/stages.h"

namespace dynref::epi {

EnhanceStageOptions EnhanceOptionsFromParams(const ParamMap& p) {
  p.RequireKnownKeys({"s", "window", "alpha", "p", "e0", "down", "w_ms", "clahe_clip", "clahe_tiles",
                      "edge_threshold", "optimise", "boa_population", "boa_iterations", "boa_switch_p",
                      "boa_sensory_c", "boa_power_a", "boa_cauchy_scale", "alpha_max", "p_min", "p_max", "seed"});
  EnhanceStageOptions o;
  o.params.s = p.GetDouble("s");
  o.params.window = int(p.GetInt("window"));
  o.params.alpha = p.GetDouble("alpha");
  o.params.p = p.GetDouble("p");
  o.params.e0 = p.GetDouble("e0");
  o.params.down = p.GetDouble("down");
  o.params.w_ms = p.GetDouble("w_ms");
  o.params.clahe_clip = p.GetDouble("clahe_clip");
  o.params.clahe_tiles = int(p.GetInt("clahe_tiles"));
  o.params.edge_threshold = p.GetDouble("edge_threshold");
  o.optimise = p.GetBool("optimise");
  o.boa.population = int(p.GetInt("boa_population"));
  o.boa.iterations = int(p.GetInt("boa_iterations"));
  o.boa.switch_p = p.GetDouble("boa_switch_p");
  o.boa.sensory_c = p.GetDouble("boa_sensory_c");
  o.boa.power_a = p.GetDouble("boa_power_a");
  o.boa.cauchy_scale = p.GetDouble("boa_cauchy_scale");
  o.alpha_max = p.GetDouble("alpha_max");
  o.p_min = p.GetDouble("p_min");
  o.p_max = p.GetDouble("p_max");
  o.seed = uint64_t(p.GetInt("seed"));
  try {
    o.params.Check();
    o.boa.Check();
    if (!(o.alpha_max > 0)) throw std::invalid_argument("alpha_max must be > 0");
    if (!(o.p_min > 0 && o.p_min < o.p_max)) throw std::invalid_argument("need 0 < p_min < p_max");
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "stage epi.enhance: " + std::string(e.what()));
  }
  return o;
}

BoaResult OptimiseEnhancement(const cv::Mat& grey8, const EnhanceStageOptions& o, EnhanceParams* params, Rng& rng,
                              int threads) {
  // Every evaluation enhances the same stretched image: its (alpha, p)-free terms once, buffers reused.
  EnhanceTerms terms(CdfStretch(grey8, params->s).stretched, *params, threads);
  EnhanceWorkspace ws;
  cv::Mat enhanced;
  const Fitness fit = [&](const std::vector<double>& x) {
    terms.Apply(x[0], x[1], enhanced, threads);
    return EnhancementFitness(enhanced, params->edge_threshold, threads, nullptr, ws);
  };
  const BoaResult r = ButterflyOptimise(fit, {0.0, o.p_min}, {o.alpha_max, o.p_max}, o.boa, rng);
  params->alpha = r.best[0];
  params->p = r.best[1];
  return r;
}

EnhanceResult SequenceEnhancer::Enhance(const cv::Mat& grey8, BoaResult* tuned, int threads) {
  if (tuned != nullptr) *tuned = BoaResult{};
  if (o_.optimise && !tuned_) {
    const BoaResult r = OptimiseEnhancement(grey8, o_, &o_.params, rng_, threads);
    if (tuned != nullptr) *tuned = r;
    tuned_ = true;
  }
  return epi::Enhance(grey8, o_.params, threads, buffers_);
}

EnhanceStage::EnhanceStage(const ParamMap& p) : enhancer_(EnhanceOptionsFromParams(p)) {}

void EnhanceStage::Run(StageContext& ctx) {
  const Frame& f = ctx.frame.view();
  trace::TraceWriter& tr = ctx.trace;
  const std::string fid = "f" + std::to_string(f.index);
  cv::Mat& grey = ctx.frame.grey_for_extraction();
  BoaResult boa;
  const EnhanceResult e = enhancer_.Enhance(grey, &boa, ctx.threads);
  const EnhanceParams& q = enhancer_.params();
  if (tr.full_enabled()) {
    // p = 0 on every record: fitness and grey statistics are no evidence of motion (README "Trace").
    if (boa.evaluations > 0) {
      for (size_t it = 0; it < boa.best_per_iteration.size(); ++it)
        tr.ProbabilityUpdate("epi.boa", trace::EntityKind::kFrame, fid,
                             {{"iteration", double(it)}, {"best_fitness", boa.best_per_iteration[it]}}, 0.0, 0.0);
      tr.ProbabilityUpdate("epi.boa", trace::EntityKind::kFrame, fid,
                           {{"alpha", q.alpha}, {"p", q.p}, {"evaluations", double(boa.evaluations)},
                            {"best_fitness", boa.best_fitness}},
                           0.0, 0.0);
    }
    const StretchResult& st = e.stretch;
    const FitnessTerms& ft = e.fitness_terms;
    tr.ProbabilityUpdate(name(), trace::EntityKind::kFrame, fid,
                         {{"I_lo", e.lo}, {"I_hi", e.hi}, {"cdf_lo_below", st.cdf_lo_below}, {"cdf_lo", st.cdf_lo},
                          {"cdf_hi_below", st.cdf_hi_below}, {"cdf_hi", st.cdf_hi}, {"alpha", q.alpha}, {"p", q.p},
                          {"sobel_sum", ft.sobel_sum}, {"edge_pixels", double(ft.edge_pixels)},
                          {"pixels", double(ft.pixels)}, {"entropy", ft.entropy}, {"fitness", e.fitness},
                          {"mean_in", e.mean_in}, {"mean_out", e.mean_out}},
                         0.0, 0.0);
  }
  grey = e.grey8;
}

}  // namespace dynref::epi
