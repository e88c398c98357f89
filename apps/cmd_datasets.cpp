// skelgrasp datasets fetch ycb ID...: download and unpack official YCB raw RGB-D captures.
// skelgrasp datasets fixture ycb-raw DIR: write the synthetic YCB-raw-layout capture of the tests.
#include <iostream>

#include "cli.h"
#include "skelgrasp/common/mesh_io.h"
#include "skelgrasp/datasets/fetch.h"
#include "skelgrasp/datasets/ycb_raw_fixture.h"

namespace skelgrasp::cli {

void registerDatasetsCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand("datasets", "Download datasets, write test fixtures");
  cmd->require_subcommand(1);

  auto* fetch = cmd->add_subcommand("fetch", "Download and unpack dataset archives");
  fetch->require_subcommand(1);
  auto* ycb = fetch->add_subcommand("ycb", "YCB raw RGB-D captures (<id>_berkeley_rgbd.tgz)");
  auto ids = std::make_shared<std::vector<std::string>>();
  auto dir = std::make_shared<std::string>("ycb_raw");
  auto base = std::make_shared<std::string>(datasets::kYcbDefaultBaseUrl);
  auto keep = std::make_shared<bool>(false);
  ycb->add_option("ID", *ids, "YCB object ids, e.g. 003_cracker_box 025_mug")->required();
  ycb->add_option("--dir", *dir, "Destination directory")->capture_default_str();
  ycb->add_option("--base-url", *base, "Archive server (file:// URLs work too)")
      ->capture_default_str();
  ycb->add_flag("--keep-archive", *keep, "Keep the downloaded .tgz files");
  ycb->callback([=, &action] {
    action = [=] {
      for (const auto& r : datasets::fetchYcbRgbd(*ids, *dir, *base, *keep)) {
        std::cout << r.id << ": " << r.folder << std::endl;
      }
      return kExitOk;
    };
  });

  auto* fixture = cmd->add_subcommand("fixture", "Write synthetic captures in dataset layouts");
  fixture->require_subcommand(1);
  auto* raw = fixture->add_subcommand(
      "ycb-raw", "A cylinder on a turntable seen by NP1, NP3, NP5 at four angles (YCB raw layout)");
  auto out = std::make_shared<std::string>();
  auto noise = std::make_shared<bool>(false);
  raw->add_option("DIR", *out, "Output folder")->required();
  raw->add_flag("--noise", *noise, "Apply the simulated Primesense error model");
  raw->callback([=, &action] {
    action = [=] {
      datasets::YcbRawFixtureSpec spec;
      spec.noise = *noise;
      const TriangleMesh object = datasets::writeYcbRawFixture(*out, spec);
      saveMesh(*out + "/ground_truth.ply", object);
      std::cout << "wrote a YCB raw fixture to " << *out << " (ground truth: ground_truth.ply)"
                << std::endl;
      return kExitOk;
    };
  });
}

}  // namespace skelgrasp::cli
