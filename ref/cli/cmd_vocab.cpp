// `dynref vocab train|info|convert`: bag-of-words vocabularies (ref/place, issue 34).
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/command.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/sha256.h"
#include "place/trainer.h"
#include "place/training_set.h"
#include "place/vocabulary.h"

namespace dynref::cli {
namespace {

struct TrainArgs {
  place::TrainingSetOptions set;
  place::TrainOptions train;
  std::string seed = "1";
  std::string out;
  std::string weighting = "tf-idf", scoring = "l1";
};

place::Vocabulary LoadVocabularyArg(const std::string& name) {
  if (name == "default") return place::Vocabulary::Default();
  return place::Vocabulary::Load(name);
}

}  // namespace

void RegisterVocabCommand(CLI::App& root, CommandList& out) {
  CLI::App* vocab = root.add_subcommand("vocab", "Bag-of-words vocabularies: train, inspect, convert (ref/place)");
  vocab->require_subcommand(1);

  auto a = std::make_shared<TrainArgs>();
  CLI::App* train = vocab->add_subcommand("train", "Train a DBoW2-compatible ORB vocabulary on sequence frames (deterministic)");
  train->add_option("--sequence", a->set.sequences, "Sequence folder (TUM layout); repeat for several")->required();
  train->add_option("--out", a->out, "Output vocabulary file (dynref format)")->required();
  train->add_option("--k", a->train.k, "Branching factor (2..20)");
  train->add_option("--levels", a->train.levels, "Depth of the tree (1..10)");
  train->add_option("--seed", a->seed, "Seed of the k-means++ stream place.vocab.kmeans");
  train->add_option("--iterations", a->train.max_iterations, "At most this many k-means passes per node");
  train->add_option("--every", a->set.every, "Use every N-th frame of each sequence");
  train->add_option("--max-frames", a->set.max_frames, "At most this many frames per sequence (0 = all)");
  train->add_option("--features", a->set.n_features, "ORB features per frame");
  train->add_option("--camera", a->set.camera, "Camera of the sequences (preset or YAML; default: auto)");
  train->add_option("--weighting", a->weighting, "tf-idf (default), tf, idf, binary");
  train->add_option("--scoring", a->scoring, "l1 (default), l2, chi-square, kl, bhattacharyya, dot-product");
  out.push_back({train, [a] {
                   a->train.seed = ParseSeed(a->seed, "--seed");
                   if (!place::ParseWeighting(a->weighting, &a->train.weighting))
                     throw InputError("--weighting", "unknown weighting '" + a->weighting + "'");
                   if (!place::ParseScoring(a->scoring, &a->train.scoring))
                     throw InputError("--scoring", "unknown scoring '" + a->scoring + "'");
                   a->train.Check();
                   a->set.Check();
                   const std::string parent = std::filesystem::path(a->out).parent_path().string();
                   if (!parent.empty()) EnsureDirectory(parent);  // fail before the long part
                   const bool tty = isatty(2) != 0;
                   auto progress = [tty](const std::string& line) {
                     if (tty) std::cerr << "vocab train: " << line << "\n";
                   };
                   const place::TrainingSet set = place::ExtractTrainingSet(a->set, progress);
                   const place::Vocabulary v = place::TrainVocabulary(set.images, a->train, progress);
                   v.Save(a->out);
                   std::cout << "vocab train: " << set.images.size() << " frames, " << set.descriptors
                             << " descriptors -> " << v.size() << " words, " << v.nodes().size() - 1
                             << " nodes, written to " << a->out << "\n";
                   return int{kExitOk};
                 }});

  auto file = std::make_shared<std::string>();
  CLI::App* info = vocab->add_subcommand("info", "Describe a vocabulary (dynref format or ORBvoc.txt; 'default' = the embedded one)");
  info->add_option("file", *file, "Vocabulary file or 'default'")->required();
  out.push_back({info, [file] {
                   const place::Vocabulary v = LoadVocabularyArg(*file);
                   std::cout << "k " << v.k() << "\nlevels " << v.levels() << "\nweighting "
                             << place::WeightingName(v.weighting()) << "\nscoring " << place::ScoringName(v.scoring())
                             << "\nnodes " << v.nodes().size() - 1 << "\nwords " << v.size() << "\nmax_depth "
                             << v.MaxDepth() << "\neffective_levels " << FormatFixed(v.EffectiveLevels(), 3)
                             << "\nsha256 " << Sha256Hex(v.Serialize()) << "\n";
                   return int{kExitOk};
                 }});

  auto in = std::make_shared<std::string>();
  auto conv_out = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>("dynref");
  CLI::App* convert = vocab->add_subcommand("convert", "Convert between dynref's format and ORB-SLAM2's text format");
  convert->add_option("file", *in, "Input vocabulary (either format, or 'default')")->required();
  convert->add_option("--out", *conv_out, "Output file")->required();
  convert->add_option("--format", *format, "dynref (default) or orbslam (ORBvoc.txt text format)");
  out.push_back({convert, [in, conv_out, format] {
                   if (*format != "dynref" && *format != "orbslam")
                     throw InputError("--format", "must be dynref or orbslam, got '" + *format + "'");
                   const place::Vocabulary v = LoadVocabularyArg(*in);
                   AtomicWriteFile(*conv_out, *format == "dynref" ? v.Serialize() : v.SerializeOrbSlamText());
                   std::cout << "vocab convert: " << v.size() << " words written to " << *conv_out << "\n";
                   return int{kExitOk};
                 }});
}

}  // namespace dynref::cli
