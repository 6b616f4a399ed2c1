// `dynref reproduce <table>`: argument parsing only; the tables live in ref/reproduce.
#include <iostream>
#include <memory>

#include "cli/command.h"
#include "core/error.h"
#include "reproduce/blur_tables.h"
#include "reproduce/epi_slam_tables.h"
#include "reproduce/epi_tables.h"
#include "reproduce/mgd_tables.h"
#include "reproduce/sgdo_table6.h"
#include "reproduce/semantic_tables.h"
#include "reproduce/sgdo_tables.h"
#include "reproduce/table_list.h"

namespace dynref::cli {

void RegisterReproduceCommand(CLI::App& root, CommandList& out) {
  CLI::App* rep = root.add_subcommand("reproduce", "Reproduce a paper table end to end on synthetic data");
  rep->require_subcommand(0, 1);
  auto list = std::make_shared<bool>(false);
  rep->add_flag("--list", *list, "Name every table with a runnable row, its paper and its report");

  // SGDO-SLAM (seed 001) Table 6, the ablation.
  auto a = std::make_shared<reproduce::Table6Args>();
  auto seeds6 = std::make_shared<std::vector<std::string>>();
  auto seed6 = std::make_shared<std::string>();
  CLI::App* app = rep->add_subcommand(
      "sgdo-table6", "SGDO-SLAM Table 6 (ablation): synth + orb + every sgdo variant + ATE + P/R + Markdown, over seeds");
  app->add_option("--out", a->out, "Markdown report (default " + a->out + ")");
  app->add_option("--work", a->work, "Working folder <work>/seed<S>/{seq,runs} (default " + a->work + ")");
  app->add_option("--frames", a->frames, "Frames per synthetic sequence (default 300)");
  auto* seeds_opt = app->add_option("--seeds", *seeds6, "Synthesis seeds: list and ranges, e.g. 1-5 or 1,2,7 (default 1-3)")
                        ->delimiter(',');
  app->add_option("--seed", *seed6, "One synthesis seed (same as --seeds S)")->excludes(seeds_opt);
  app->add_option("--detections", a->detections,
                  "Synthetic detection mode: ideal | yolo-like | sparseinst-like (default yolo-like)");
  app->add_option("--sequences", a->sequences, "Presets (default the five of Table 6)")->delimiter(',');
  app->add_option("--variants", a->variants, "Config names of the columns to run (default all: orb, sgdo_G, ..., sgdo_vote)")
      ->delimiter(',');
  app->add_option("--sensitivity", a->sensitivity, "Presets for the eta/lambda sweep (default walking_xyz; 'none' = skip)")
      ->delimiter(',');
  app->add_flag("--reuse", a->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
  app->add_flag("--collect", a->collect,
                "Only read: sequences and runs were made by dynref synth/run (workflow/Snakefile) in --work");
  app->add_flag("--no-overlay", a->no_overlay, "Skip the overlay montage");
  out.push_back({app, [a, seeds6, seed6] {
                   if (!seed6->empty()) a->seeds = {ParseSeed(*seed6, "--seed")};
                   if (!seeds6->empty()) a->seeds = ParseSeedList(*seeds6, "--seeds");
                   if (a->sensitivity.size() == 1 && a->sensitivity[0] == "none") a->sensitivity.clear();
                   return reproduce::RunSgdoTable6(*a);
                 }});

  // SGDO-SLAM Tables 1, 2, 3, 4, 7: orb and sgdo from the same runs as Table 6.
  for (const std::string& table : reproduce::SgdoMainTables()) {
    auto t = std::make_shared<reproduce::SgdoTableArgs>();
    t->table = table;
    t->out = "reports/sgdo-" + table + ".md";
    auto seeds = std::make_shared<std::vector<std::string>>();
    const std::string name = "sgdo-" + table;
    const std::string what = [&] {
      for (const auto& e : reproduce::ReproducibleTables())
        if (e.name == name) return e.what;
      return std::string();
    }();
    CLI::App* st = rep->add_subcommand(name, "SGDO-SLAM " + table + ": " + what);
    st->add_option("--out", t->out, "Markdown report (default " + t->out + ")");
    st->add_option("--work", t->work, "Working folder <work>/seed<S>/{seq,runs}, shared with sgdo-table6 (default " + t->work + ")");
    st->add_option("--frames", t->frames, "Frames per synthetic sequence (default 300)");
    st->add_option("--seeds", *seeds, "Synthesis seeds: list and ranges (default 1-3)")->delimiter(',');
    st->add_option("--detections", t->detections, "Synthetic detection mode (default yolo-like)");
    st->add_option("--sequences", t->sequences, "Presets (default the five of the paper's TUM tables)")->delimiter(',');
    st->add_flag("--reuse", t->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
    st->add_flag("--collect", t->collect, "Only read: sequences and runs were made by dynref synth/run (workflow/Snakefile)");
    out.push_back({st, [t, seeds] {
                     if (!seeds->empty()) t->seeds = ParseSeedList(*seeds, "--seeds");
                     return reproduce::RunSgdoTable(*t);
                   }});
  }

  // Motion-blur SLAM (seed 003): Tables 1-2 and Tables 3-4 + Fig. 12.
  for (const std::string table : {"table1", "table3"}) {
    auto b = std::make_shared<reproduce::BlurTableArgs>();
    b->table = table;
    b->out = "reports/blur-" + table + ".md";
    b->work = "dynref-work/blur";  // shared by both tables: with --reuse the second reuses sequences and blur runs
    b->sequences = reproduce::BlurTableDefaultSequences(table);
    auto seeds = std::make_shared<std::vector<std::string>>();
    auto sweep = std::make_shared<std::vector<std::string>>(b->sweep);
    auto no_blur = std::make_shared<bool>(false);
    CLI::App* bt = rep->add_subcommand(
        "blur-" + table, table == "table1"
                             ? "Motion-blur SLAM Tables 1-2: ATE of orb, sgdo and blur on blurred synthetic TUM/Bonn analogues, over seeds"
                             : "Motion-blur SLAM Tables 3-4 + Fig. 12: ablation ATE, per-module ms, compensation/depth fusion vs truth, dilation and theta sweeps");
    bt->add_option("--out", b->out, "Markdown report (default " + b->out + ")");
    bt->add_option("--work", b->work, "Working folder for sequences and runs (default " + b->work + ")");
    bt->add_option("--frames", b->frames, "Frames per synthetic sequence (default 300)");
    bt->add_option("--seeds", *seeds, "Synthesis seeds: list and ranges, e.g. 1-5 or 1,2,7 (default 1-3)")->delimiter(',');
    bt->add_option("--detections", b->detections, "Synthetic detection mode (default sparseinst-like)");
    bt->add_option("--sequences", b->sequences, "Presets (default the table's)")->delimiter(',');
    if (table == "table3")
      bt->add_option("--sweep", *sweep, "Presets of the dilation/theta sweeps (default walking_xyz; 'none' = skip)")
          ->delimiter(',');
    bt->add_flag("--no-blur", *no_blur, "Render sharp frames (masks then drop as without blur)");
    bt->add_flag("--reuse", b->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
    bt->add_flag("--collect", b->collect, "Only read: sequences and runs already in --work (made by an earlier call or dynref synth/run)");
    out.push_back({bt, [b, seeds, sweep, no_blur] {
                     if (!seeds->empty()) b->seeds = ParseSeedList(*seeds, "--seeds");
                     b->sweep = *sweep;
                     if (b->sweep.size() == 1 && b->sweep[0] == "none") b->sweep.clear();
                     b->blur = !*no_blur;
                     return reproduce::RunBlurTable(*b);
                   }});
  }

  // Enhanced-epipolar SLAM (seed 004): Table 1 (keypoints, enhancement) and Table 2 (matching).
  for (const std::string table : {"table1", "table2"}) {
    auto e = std::make_shared<reproduce::EpiTableArgs>();
    e->table = table;
    e->out = "reports/epi-" + table + ".md";
    auto seeds = std::make_shared<std::vector<std::string>>();
    CLI::App* et = rep->add_subcommand(
        "epi-" + table, table == "table1"
                            ? "Seed 004 Table 1: ORB/SIFT keypoints per frame on raw vs enhanced (Module A) grey, normal and low light"
                            : "Seed 004 Table 2: ORB/SIFT x BF/MNN2 matching precision against exact synthetic correspondences");
    et->add_option("--out", e->out, "Markdown report (default " + e->out + ")");
    et->add_option("--work", e->work, "Working folder for sequences (default dynref-work/epi)");
    et->add_option("--frames", e->frames, "Frames per synthetic sequence (default 60)");
    et->add_option("--seeds", *seeds, "Synthesis seeds: list and ranges (default 1-3)")->delimiter(',');
    if (table == "table2") {
      et->add_option("--gap", e->gap, "Frame distance of a matched pair (default 5)");
      et->add_option("--features", e->features, "Features per image (default 500, paper Sec. 4.2)");
    }
    et->add_flag("--reuse", e->reuse, "Reuse sequences of an earlier call with identical inputs");
    out.push_back({et, [e, seeds] {
                     if (!seeds->empty()) e->seeds = ParseSeedList(*seeds, "--seeds");
                     return reproduce::RunEpiTable(*e);
                   }});
  }

  {  // Enhanced-epipolar SLAM (seed 004): Tables 3-7 (SLAM runs, normal and low light).
    auto e = std::make_shared<reproduce::EpiSlamTableArgs>();
    e->sequences = reproduce::EpiSlamDefaultSequences();
    e->ablation_sequences = reproduce::EpiSlamDefaultAblationSequences();
    auto seeds = std::make_shared<std::vector<std::string>>();
    CLI::App* et = rep->add_subcommand(
        "epi-table3", "Seed 004 Tables 3-7: ATE of orb and epi (A + C) on TUM/Bonn analogues in normal and low light, "
                      "the A/C ablation, Module C's mask-vote accuracy against the ground truth, ms/frame, over seeds");
    et->add_option("--out", e->out, "Markdown report (default " + e->out + ")");
    et->add_option("--work", e->work, "Working folder <work>/seed<S>/<lighting>/{seq,runs} (default " + e->work + ")");
    et->add_option("--frames", e->frames, "Frames per synthetic sequence (default 300)");
    et->add_option("--seeds", *seeds, "Synthesis seeds: list and ranges (default 1-3)")->delimiter(',');
    et->add_option("--detections", e->detections, "Synthetic detection mode (default yolo-like)");
    et->add_option("--sequences", e->sequences, "Presets (default the paper's TUM and Bonn analogues)")->delimiter(',');
    et->add_option("--ablation-sequences", e->ablation_sequences, "Presets of the A/C ablation (default walking_static,crowd)")
        ->delimiter(',');
    et->add_option("--timing-sequence", e->timing_sequence, "Preset of the Table 7 timing runs (default walking_xyz)");
    et->add_flag("--reuse", e->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
    et->add_flag("--collect", e->collect, "Only read: sequences and runs already in --work");
    out.push_back({et, [e, seeds] {
                     if (!seeds->empty()) e->seeds = ParseSeedList(*seeds, "--seeds");
                     return reproduce::RunEpiSlamTable(*e);
                   }});
  }

  // MGD-SLAM (seed 000): Table 2 (+ dynamic-feature P/R of the cue ablations) and Tables 4-6.
  for (const std::string table : {"table2", "table4"}) {
    auto m = std::make_shared<reproduce::MgdTableArgs>();
    m->table = table;
    m->out = "reports/mgd-" + table + ".md";
    m->sequences = reproduce::MgdTableDefaultSequences(table);
    auto seeds = std::make_shared<std::vector<std::string>>();
    CLI::App* mt = rep->add_subcommand(
        "mgd-" + table, table == "table2"
                            ? "MGD-SLAM Table 2: ATE of orb, mgd-nd, mgd on 8 synthetic walking/sitting analogues, and "
                              "dynamic point/line precision/recall/F1 of mgd and its cue ablations, over seeds"
                            : "MGD-SLAM Tables 4-6: MGD-SLAM-nD ablation ATE and RPE on the walking analogues, "
                              "per-module ms/frame of mgd, over seeds");
    mt->add_option("--out", m->out, "Markdown report (default " + m->out + ")");
    mt->add_option("--work", m->work, "Working folder <work>/seed<S>/{seq,runs}, shared by mgd-table2/4 (default " + m->work + ")");
    mt->add_option("--frames", m->frames, "Frames per synthetic sequence (default 300)");
    mt->add_option("--seeds", *seeds, "Synthesis seeds: list and ranges (default 1-3)")->delimiter(',');
    mt->add_option("--detections", m->detections, "Synthetic detection mode (default yolo-like)");
    mt->add_option("--sequences", m->sequences, "Presets (default the table's)")->delimiter(',');
    if (table == "table2")
      mt->add_flag("--no-ablations", m->no_ablations, "Skip the cue ablations and the precision/recall runs");
    mt->add_flag("--reuse", m->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
    mt->add_flag("--collect", m->collect, "Only read: sequences and runs already in --work");
    out.push_back({mt, [m, seeds] {
                     if (!seeds->empty()) m->seeds = ParseSeedList(*seeds, "--seeds");
                     return reproduce::RunMgdTable(*m);
                   }});
  }

  // Semantic mapping (seed 002): map files per stage, map quality, non-prior dynamic objects.
  {
    auto m = std::make_shared<reproduce::SemanticTableArgs>();
    auto seeds = std::make_shared<std::vector<std::string>>();
    CLI::App* mt = rep->add_subcommand(
        "semantic-filesizes",
        "Seed 002: map files per stage (raw, SOR, voxel, octree, grid) beside the paper's sizes, map accuracy/"
        "completeness/ghosts of semantic vs no removal vs sgdo, non-prior dynamic P/R, over seeds");
    mt->add_option("--out", m->out, "Markdown report (default " + m->out + ")");
    mt->add_option("--work", m->work, "Working folder <work>/seed<S>/{seq,runs} (default " + m->work + ")");
    mt->add_option("--frames", m->frames, "Frames per synthetic sequence (default 150)");
    mt->add_option("--seeds", *seeds, "Synthesis seeds: list and ranges (default 1-3)")->delimiter(',');
    mt->add_option("--detections", m->detections, "Synthetic detection mode (default yolo-like)");
    mt->add_option("--sequences", m->sequences, "Presets (default the paper's TUM analogues + walking_xyz + moving_box)")
        ->delimiter(',');
    mt->add_flag("--reuse", m->reuse, "Reuse sequences/runs of an earlier call with identical inputs");
    mt->add_flag("--collect", m->collect, "Only read: sequences and runs already in --work");
    out.push_back({mt, [m, seeds] {
                     if (!seeds->empty()) m->seeds = ParseSeedList(*seeds, "--seeds");
                     return reproduce::RunSemanticTable(*m);
                   }});
  }

  // `dynref reproduce --list` (the node itself; last, so a parsed table wins the dispatch in main).
  out.push_back({rep, [list] {
                   if (!*list)
                     throw InputError("reproduce", "name a table (dynref reproduce --list shows them)");
                   std::cout << "table\tpaper\treport\twhat\n";
                   for (const auto& e : reproduce::ReproducibleTables())
                     std::cout << e.name << "\t" << e.paper << "\t" << e.Report() << "\t" << e.what << "\n";
                   return kExitOk;
                 }});
}

}  // namespace dynref::cli
