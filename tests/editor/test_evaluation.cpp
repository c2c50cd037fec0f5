// The evaluation controller: previews run in the background, recompute only what an edit affects, hit the
// cache after undo, cancel superseded runs, and builds write at full resolution.
#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "cli/resolution_presets.h"
#include "editor/model/build_resolutions.h"
#include "editor/model/document.h"
#include "editor/model/evaluation_controller.h"
#include "support/editor_test_support.h"

namespace orogen::editor {
namespace {

using Phase = NodeRunState::Phase;

std::map<std::string, NodeStatus> statuses(const PreviewResult& r) {
  std::map<std::string, NodeStatus> out;
  for (const auto& [id, report] : r.reports) out[id] = report.status;
  return out;
}

TEST(EvaluationController, PreviewUsesThePreviewResolutionOfTheSameWorld) {
  EvaluationController ec;
  GraphDomain d;
  d.origin = {100, 200};
  d.size = {4000, 2000};
  d.resolution = {4096, 2048};
  const Domain p = ec.preview_domain(d);
  EXPECT_EQ(p.resolution, glm::ivec2(512, 256));
  EXPECT_EQ(p.min_corner(), glm::dvec2(100, 200));
  EXPECT_NEAR(p.max_corner().x, 4100, 1e-9);
  EXPECT_NEAR(p.max_corner().y, 2200, 1e-9);
  ec.set_preview_resolution(256);
  EXPECT_EQ(ec.preview_domain(d).resolution, glm::ivec2(256, 128));
  d.resolution = {64, 32};  // never more than the build
  EXPECT_EQ(ec.preview_domain(d).resolution, glm::ivec2(64, 32));
}

TEST(EvaluationController, EditRecomputesOnlyDownstreamAndUndoHitsTheCache) {
  EvaluationController ec;
  Document doc(test::chain_graph());
  ec.request_preview(doc.graph(), {"out"}, doc.content_revision());
  ec.wait_idle();
  auto first = ec.preview();
  ASSERT_TRUE(first);
  EXPECT_EQ(statuses(*first),
            (std::map<std::string, NodeStatus>{
                {"src", NodeStatus::Computed}, {"mid", NodeStatus::Computed}, {"out", NodeStatus::Computed}}));
  ASSERT_TRUE(first->outputs.count("out"));
  const auto out_before = std::get<HeightfieldPtr>(first->outputs.at("out").at(0));
  EXPECT_EQ(out_before->domain, ec.preview_domain(doc.graph().domain));

  // Edit the middle node: src is cached, mid and out are recomputed.
  doc.set_param("mid", "weight", 0.9);
  doc.connect({"src", "out"}, "mid", "b");
  ec.request_preview(doc.graph(), {"out"}, doc.content_revision());
  ec.wait_idle();
  auto second = ec.preview();
  EXPECT_EQ(statuses(*second),
            (std::map<std::string, NodeStatus>{
                {"src", NodeStatus::Cached}, {"mid", NodeStatus::Computed}, {"out", NodeStatus::Computed}}));
  EXPECT_EQ(ec.node_state("src").phase, Phase::Cached);
  EXPECT_EQ(ec.node_state("mid").phase, Phase::Computed);
  EXPECT_GT(second->serial, first->serial);
  EXPECT_EQ(second->revision, doc.content_revision());

  // Undo both edits: everything is a cache hit and the result is the first one's.
  doc.undo();
  doc.undo();
  ec.request_preview(doc.graph(), {"out"}, doc.content_revision());
  ec.wait_idle();
  auto third = ec.preview();
  for (const auto& [id, status] : statuses(*third)) EXPECT_EQ(status, NodeStatus::Cached) << id;
  EXPECT_EQ(std::get<HeightfieldPtr>(third->outputs.at("out").at(0))->data, out_before->data);
  EXPECT_EQ(ec.node_state("out").phase, Phase::Cached);
  EXPECT_GT(ec.node_state("out").milliseconds, 0.0) << "the last compute time is kept";
}

TEST(EvaluationController, EditMarksTheAffectedNodesOutOfDate) {
  EvaluationController ec;
  Document doc(test::chain_graph());
  ec.request_preview(doc.graph(), {"out"}, doc.content_revision());
  ec.wait_idle();
  doc.set_param("mid", "weight", 0.75);
  doc.connect({"src", "out"}, "mid", "b");
  // Preview only src: mid and out are not evaluated, and show that they are out of date.
  ec.request_preview(doc.graph(), {"src"}, doc.content_revision());
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("src").phase, Phase::Cached);
  EXPECT_EQ(ec.node_state("mid").phase, Phase::Stale);
  EXPECT_EQ(ec.node_state("out").phase, Phase::Stale);
  EXPECT_EQ(ec.node_state("scatter").phase, Phase::Unknown);
  // Moving a node changes no key: nothing becomes stale.
  ec.request_preview(doc.graph(), {"out"}, doc.content_revision());
  ec.wait_idle();
  doc.move_nodes({"mid"}, {5, 5});
  ec.request_preview(doc.graph(), {"src"}, doc.content_revision());
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("out").phase, Phase::Computed);
}

TEST(EvaluationController, NewRequestCancelsTheRunItSupersedes) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  g.add_node("EdSlow", "slow");
  g.connect({"out", "out"}, "slow", "in");
  g.set_param("slow", "milliseconds", std::int64_t{20000});
  const auto start = std::chrono::steady_clock::now();
  ec.request_preview(g, {"slow"}, 1);
  // Wait until the slow node is running, then supersede it with a quick request.
  while (ec.node_state("slow").phase != Phase::Computing) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_TRUE(ec.preview_busy());
  g.set_param("slow", "milliseconds", std::int64_t{0});
  ec.request_preview(g, {"slow"}, 2);
  ec.wait_idle();
  const auto elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_LT(elapsed, std::chrono::seconds(15)) << "the 20 s run was cancelled";
  auto r = ec.preview();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->revision, 2u) << "only the newest request's result is published";
  EXPECT_EQ(ec.node_state("slow").phase, Phase::Computed);
}

TEST(EvaluationController, FailuresAreReportedPerNode) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  g.disconnect("mid", "a");  // mid's required input: mid fails, out is skipped
  ec.request_preview(g, {"out"}, 1);
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("mid").phase, Phase::Failed);
  EXPECT_FALSE(ec.node_state("mid").message.empty());
  EXPECT_EQ(ec.node_state("out").phase, Phase::Skipped);
  EXPECT_NE(ec.node_state("out").message.find("'mid'"), std::string::npos) << ec.node_state("out").message;
}

TEST(EvaluationController, BuildEvaluatesAtFullResolution) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  g.domain.resolution = {200, 100};
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("build");
  ec.start_build(g, policy);
  ec.wait_idle();
  const auto status = ec.build_status();
  EXPECT_TRUE(status.finished);
  EXPECT_TRUE(status.ok);
  EXPECT_FALSE(status.running);
  EXPECT_EQ(status.fraction, 1.0);
  EXPECT_EQ(status.domain.resolution, glm::ivec2(200, 100));
}

TEST(BuildResolutions, TheFilesQuickSizesAndTheEnginePresetsWithSquareCells) {
  GraphDomain d;
  d.size = {4096, 4096};
  d.resolution = {257, 257};
  auto choices = build_resolutions(d);
  ASSERT_FALSE(choices.empty());
  EXPECT_EQ(choices.front().kind, BuildResolution::Kind::File);
  EXPECT_EQ(choices.front().samples, glm::ivec2(257, 257));
  EXPECT_EQ(choices.front().label(), "257 x 257 (the file's)");
  const auto find = [&](const std::string& name) -> const BuildResolution* {
    for (const auto& c : choices)
      if (c.name == name) return &c;
    return nullptr;
  };
  ASSERT_TRUE(find("129"));
  EXPECT_EQ(find("129")->samples, glm::ivec2(129, 129));
  EXPECT_FALSE(find("257")) << "the file's size is offered once";
  // Every preset of the CLI's table, from that table.
  for (const auto& p : cli::resolution_presets()) {
    ASSERT_TRUE(find(p.name)) << p.name;
    EXPECT_EQ(find(p.name)->samples, glm::ivec2(p.samples, p.samples));
  }
  EXPECT_EQ(find("unreal-1009")->label(), "unreal-1009: 1009 x 1009");

  // A domain twice as wide as high: y follows the aspect, as orogen eval --resolution N does.
  d.size = {4096, 2048};
  d.resolution = {513, 257};
  choices = build_resolutions(d);
  EXPECT_EQ(find("129")->samples, glm::ivec2(129, 65));
  EXPECT_EQ(find("unreal-1009")->samples, glm::ivec2(1009, 505));
  // An awkward aspect: only the sizes that keep square cells are offered.
  d.size = {1000, 333};
  d.resolution = {1001, 334};
  choices = build_resolutions(d);
  EXPECT_LT(choices.size(), 5 + cli::resolution_presets().size());
  for (const auto& c : choices) {
    const double sx = d.size.x / (c.samples.x - 1), sy = d.size.y / (c.samples.y - 1);
    EXPECT_NEAR(sx, sy, 1e-9 * sx) << c.label();
  }
}

TEST(EvaluationController, BuildAtAChosenResolutionKeepsTheWorld) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  g.domain.size = {1000, 500};
  g.domain.resolution = {201, 101};
  const auto choices = build_resolutions(g.domain);
  const auto quick = std::find_if(choices.begin(), choices.end(), [](const auto& c) { return c.name == "129"; });
  ASSERT_NE(quick, choices.end());
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("build_resolution");
  ec.start_build(graph_at_resolution(g, quick->samples), policy);
  ec.wait_idle();
  const auto status = ec.build_status();
  EXPECT_TRUE(status.ok);
  EXPECT_EQ(status.domain.resolution, glm::ivec2(129, 65));
  EXPECT_EQ(status.domain.size(), glm::dvec2(1000, 500)) << "the same world rectangle";
}

TEST(EvaluationController, BuildLeavesOutANodeNotWiredYet) {
  EvaluationController ec;
  Graph g;
  g.domain.resolution = {33, 33};
  g.add_node("FBM", "noise");
  g.add_node("WriteHeightfield", "save");
  g.connect({"noise", "out"}, "save", "in");
  g.add_node("Slope", "loose");  // just added from the palette: no output needs it
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("build-left-out");
  ec.start_build(g, policy);
  ec.wait_idle();
  const auto status = ec.build_status();
  EXPECT_TRUE(status.ok) << (status.failures.empty() ? "" : status.failures.front());
  EXPECT_EQ(status.left_out, std::vector<std::string>{"loose"});
}

TEST(EvaluationController, NodeStatesShowWhatTheBuildDid) {
  EvaluationController ec;
  std::atomic<int> notified{0};
  ec.set_on_change([&] { ++notified; });
  Graph g = test::chain_graph();
  ec.request_preview(g, {"out"}, 1);
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("mid").phase, Phase::Computed);
  g.disconnect("mid", "a");  // the build fails on mid (the preview did not see that graph)
  ec.start_build(g, {});
  ec.wait_idle();
  // The preview and the build woke the UI (the call follows the end of the run, so wait a moment for it).
  for (int k = 0; k < 5000 && notified < 2; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_GE(notified.load(), 2);
  EXPECT_EQ(ec.node_state("mid").phase, Phase::Failed);
  EXPECT_EQ(ec.node_state("mid").message.rfind("build: ", 0), 0u) << ec.node_state("mid").message;
  EXPECT_EQ(ec.node_state("out").phase, Phase::Computed) << "a skip in the build keeps the preview's state";
}

TEST(EvaluationController, BuildStatesHoldUntilAnEdit) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  ec.request_preview(g, {"out"}, 1);  // scatter is never previewed
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("scatter").phase, Phase::Unknown);
  ec.start_build(g, {});
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("scatter").phase, Phase::Computed);
  EXPECT_TRUE(ec.node_state("scatter").by_build);
  ec.request_preview(g, {"mid"}, 2);  // another node previewed: the build's state holds
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("scatter").phase, Phase::Computed);
  g.set_param("scatter", "count", std::int64_t{5});  // an edit of it: out of date
  ec.request_preview(g, {"mid"}, 3);
  ec.wait_idle();
  EXPECT_EQ(ec.node_state("scatter").phase, Phase::Stale);
}

TEST(EvaluationController, ThumbnailsOfEveryNodeAtLowResolutionLeaveStatesAlone) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  g.domain.size = {2000.0, 1000.0};
  ec.request_thumbnails(g, 7);
  ec.request_preview(g, {"mid"}, 7);  // a preview goes first, cancelling the thumbnails, which then resume
  ec.wait_idle();
  const auto t = ec.thumbnails();
  ASSERT_TRUE(t);
  EXPECT_EQ(t->revision, 7u);
  for (const char* id : {"src", "mid", "out", "scatter"}) EXPECT_TRUE(t->outputs.count(id)) << id;
  const auto& h = std::get<HeightfieldPtr>(t->outputs.at("out").front());
  EXPECT_EQ(h->domain.resolution,
            glm::ivec2(EvaluationController::kThumbnailResolution, EvaluationController::kThumbnailResolution / 2));
  // The world rectangle points and curves are drawn in.
  EXPECT_EQ(t->domain.resolution, h->domain.resolution);
  EXPECT_EQ(t->domain.max_corner(), h->domain.max_corner());
  EXPECT_EQ(ec.node_state("out").phase, Phase::Unknown) << "thumbnails do not change the node states";
  EXPECT_EQ(ec.node_state("mid").phase, Phase::Computed);
}

TEST(EvaluationController, BuildCanBeCancelled) {
  EvaluationController ec;
  Graph g = test::chain_graph();
  g.add_node("EdSlow", "slow");
  g.connect({"out", "out"}, "slow", "in");
  g.set_param("slow", "milliseconds", std::int64_t{30000});
  ec.start_build(g, {});
  while (ec.build_status().fraction <= 0.0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ec.cancel_build();
  ec.wait_idle();
  const auto status = ec.build_status();
  EXPECT_TRUE(status.finished);
  EXPECT_TRUE(status.cancelled);
  EXPECT_FALSE(status.ok);
}

}  // namespace
}  // namespace orogen::editor
