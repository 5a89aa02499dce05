// detect_cones and pnp_solve as a user runs them: a non-zero exit status when any input failed,
// and one stderr line per failure naming the file or the case.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace {

std::string TempPath(const std::string& name) {
  return "/tmp/cone_tracker_cli_test_" + std::to_string(getpid()) + "_" + name;
}

struct ToolRun {
  int status = -1;
  std::string err;
};

ToolRun RunTool(const std::string& exe, const std::string& args) {
  const std::string err_path = TempPath("stderr.txt");
  const int raw = std::system((exe + " " + args + " >/dev/null 2>" + err_path).c_str());
  ToolRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(err_path);
  r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  std::remove(err_path.c_str());
  return r;
}

int Lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

TEST(DetectConesCli, UnreadableImagesExitOneWithALineEach) {
  const std::string text = TempPath("not_an_image.png"), missing = TempPath("missing.png"), out = TempPath("d.jsonl");
  std::ofstream(text) << "not a PNG\n";
  const ToolRun r = RunTool(DETECT_CONES_EXE, "--output " + out + " " + text + " " + missing);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("detect_cones: " + text + ": cannot read the image"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("detect_cones: " + missing + ": cannot read the image"), std::string::npos) << r.err;
  EXPECT_EQ(Lines(r.err), 2) << r.err;
  // The JSON lines still say which image failed.
  std::ifstream in(out);
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) lines += line.find("\"error\"") != std::string::npos ? 1 : 0;
  EXPECT_EQ(lines, 2);
  std::remove(text.c_str());
  std::remove(out.c_str());
}

TEST(DetectConesCli, UnwritableOutputExitsOne) {
  const ToolRun r = RunTool(DETECT_CONES_EXE, "--output /nonexistent_dir/d.jsonl /nonexistent.png");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot write /nonexistent_dir/d.jsonl"), std::string::npos) << r.err;
}

// A camera 5 m in front of five points on the model's z = 0 plane, identity rotation.
std::string GoodCase() {
  const double pts[5][2] = {{0.0, 0.0}, {0.5, 0.1}, {-0.4, 0.3}, {0.2, -0.5}, {-0.3, -0.2}};
  std::string model, image;
  for (const auto& p : pts) {
    model += std::string(model.empty() ? "" : ",") + "[" + std::to_string(p[0]) + "," + std::to_string(p[1]) + ",0]";
    image += std::string(image.empty() ? "" : ",") + "[" + std::to_string(500.0 * p[0] / 5.0 + 320.0) + "," +
             std::to_string(500.0 * p[1] / 5.0 + 240.0) + "]";
  }
  return R"({"K":[500,500,320,240],"model":[)" + model + R"(],"image":[)" + image + R"(],"sigma_px":1})";
}

TEST(PnpSolveCli, AllCasesSolvedExitsZero) {
  const std::string in = TempPath("good.jsonl"), out = TempPath("good_out.jsonl");
  std::ofstream(in) << GoodCase() << "\n" << GoodCase() << "\n";
  const ToolRun r = RunTool(PNP_SOLVE_EXE, "--input " + in + " --output " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  std::remove(in.c_str());
  std::remove(out.c_str());
}

TEST(PnpSolveCli, FailedCasesExitOneWithALineEach) {
  const std::string in = TempPath("bad.jsonl"), out = TempPath("bad_out.jsonl");
  std::ofstream(in) << GoodCase() << "\n"
                    << "not json\n"
                    << R"({"K":[500,500,320],"model":[],"image":[]})"
                    << "\n";
  const ToolRun r = RunTool(PNP_SOLVE_EXE, "--input " + in + " --output " + out);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("pnp_solve: " + in + ": line 2: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pnp_solve: " + in + ": line 3: bad input: K must be [fx, fy, cx, cy]"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("line 1:"), std::string::npos) << r.err;
  EXPECT_EQ(Lines(r.err), 3) << r.err;  // two cases and the summary
  std::remove(in.c_str());
  std::remove(out.c_str());
}

TEST(PnpSolveCli, RansacListsInliersAndRefusesABadThreshold) {
  const std::string in = TempPath("ransac.jsonl"), out = TempPath("ransac_out.jsonl");
  std::ofstream(in) << GoodCase() << "\n";
  const ToolRun r = RunTool(PNP_SOLVE_EXE, "--ransac-px 2 --input " + in + " --output " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  std::string line;
  std::getline(std::ifstream(out), line);
  EXPECT_NE(line.find(R"("inliers":5,"outliers":[])"), std::string::npos) << line;
  const ToolRun bad = RunTool(PNP_SOLVE_EXE, "--ransac-px -1 --input " + in + " --output " + out);
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("pnp_solve: --ransac-px '-1' is not a positive number of pixels"), std::string::npos)
      << bad.err;
  std::remove(in.c_str());
  std::remove(out.c_str());
}

TEST(PnpSolveCli, UnreadableInputExitsOne) {
  const ToolRun r = RunTool(PNP_SOLVE_EXE, "--input /nonexistent.jsonl --output -");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot open /nonexistent.jsonl"), std::string::npos) << r.err;
  const ToolRun dir = RunTool(PNP_SOLVE_EXE, "--input /tmp --output -");  // a directory opens but cannot be read
  EXPECT_EQ(dir.status, 1);
  EXPECT_NE(dir.err.find("reading /tmp failed"), std::string::npos) << dir.err;
}

// calibrate_cone_colour (a Python script, run as rosrun runs it): a box with no cone pixels is refused
// with the reason, and with no usable box nothing is written; a box around an orange cone gives a
// model that detect_cones loads through its config's colour_model.
TEST(CalibrateConeColourCli, EmptyBoxIsRefusedAndAConeBoxGivesALoadableModel) {
  const std::string exe = std::string(CONE_TRACKER_SOURCE_DIR) + "/scripts/calibrate_cone_colour";
  cv::Mat img(240, 320, CV_8UC3, cv::Scalar(70, 62, 60));  // BGR: dark asphalt
  const std::vector<cv::Point> cone = {{160, 40}, {120, 200}, {200, 200}};
  cv::fillConvexPoly(img, cone, cv::Scalar(20, 95, 250));  // orange
  const std::string image = TempPath("cone.png"), boxes = TempPath("boxes.csv"), model = TempPath("model.yaml");
  ASSERT_TRUE(cv::imwrite(image, img));
  std::ofstream(boxes) << "image,x,y,w,h\n" << image << ",10,10,60,80\n";  // asphalt only
  const ToolRun empty = RunTool(exe, "--boxes " + boxes + " --output " + model + " " + image);
  EXPECT_EQ(empty.status, 1) << empty.err;
  EXPECT_NE(empty.err.find(image + ": box 1 refused: no cone-coloured pixels: 0 of the"), std::string::npos)
      << empty.err;
  EXPECT_NE(empty.err.find("no usable cone box (1 refused); nothing written"), std::string::npos) << empty.err;
  EXPECT_FALSE(std::ifstream(model).good());

  std::ofstream(boxes) << image << ",115,38,90,165\n" << image << ",250,150,40,60\n";
  const ToolRun ok = RunTool(exe, "--boxes " + boxes + " --output " + model + " " + image);
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_NE(ok.err.find("box 2 refused"), std::string::npos) << ok.err;  // the second box, on asphalt
  const std::string config = TempPath("config.yaml"), out = TempPath("d.jsonl");
  std::ofstream(config) << "colour_model: " << model << "\nreject_bad_outline: false\n";
  const ToolRun det = RunTool(DETECT_CONES_EXE, "--config " + config + " --output " + out + " " + image);
  EXPECT_EQ(det.status, 0) << det.err;
  std::ifstream in(out);
  const std::string line((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(line.find("\"cones\":[{\"area\""), std::string::npos) << line;
  for (const auto& p : {image, boxes, model, config, out}) std::remove(p.c_str());
}

}  // namespace
