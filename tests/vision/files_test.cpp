// Marker and camera files, chessboard calibration, the CLI's errors.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "support/cli_runner.hpp"
#include "support/png_bomb.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/vision/camera_calibration.hpp"
#include "vision_test_util.hpp"

namespace trueaxis::vision {
namespace {

namespace fs = std::filesystem;

TEST(MarkerFile, ReadsTheExampleAndRoundTrips) {
  const auto m = ReadMarkerFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/vision/marker.toml");
  EXPECT_DOUBLE_EQ(m.circle_spacing_mm, 40);
  EXPECT_NEAR(m.Cbb2Mm(), 80 / std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(m.EpsilonInSeedRange());
  MarkerDescription changed = m;
  changed.reference_k1 = 1.000123456;
  const auto back = ParseMarkerToml(MarkerToml(changed), "round.toml");
  EXPECT_NEAR(back.reference_k1, changed.reference_k1, 1e-9);
  EXPECT_DOUBLE_EQ(back.distance_mm, m.distance_mm);
}

TEST(MarkerFile, RefusesTyposAndOutOfRangeValuesNamingTheLine) {
  try {
    ParseMarkerToml("[marker]\ncircle_spacing_mm = 40\ndiameter_mm = 80\ninkwidth_mm = 1\n", "m.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inkwidth_mm"), std::string::npos) << e.what();
  }
  try {
    ParseMarkerToml("[marker]\ncircle_spacing_mm = 40\ndiameter_mm = 80\n[credibility]\nepsilon = 0.2\n", "m.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 5) << e.what();
    EXPECT_NE(std::string(e.what()).find("epsilon"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseMarkerToml("[spindle]\nlength_mm = 300\n", "m.toml"), InputError);  // no [marker]
}

TEST(CameraFile, RoundTripsAndNamesMissingFields) {
  const fs::path dir = fs::temp_directory_path() / "trueaxis_vision_files_test";
  fs::create_directories(dir);
  const auto cam = testing::TestCamera();
  WriteCameraFile((dir / "cam.yml").string(), cam);
  const auto back = ReadCameraFile((dir / "cam.yml").string());
  EXPECT_DOUBLE_EQ(back.fx, cam.fx);
  EXPECT_DOUBLE_EQ(back.k1, cam.k1);
  EXPECT_EQ(back.width_px, 640);
  std::ofstream((dir / "bad.yml").string()) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n";
  try {
    ReadCameraFile((dir / "bad.yml").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_matrix"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadCameraFile((dir / "none.yml").string()), InputError);
}

// The sweep's A3: a matrix whose rows × cols disagree with its data, and a
// file cut inside a matrix, leaked OpenCV's assertion text without a field.
TEST(CameraFile, MalformedMatricesNameTheField) {
  const fs::path dir = fs::temp_directory_path() / "trueaxis_vision_files_test";
  fs::create_directories(dir);
  const std::string head = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n";
  const std::string rows2 = head + "camera_matrix: !!opencv-matrix\n   rows: 2\n   cols: 3\n   dt: d\n"
                                   "   data: [ 1454.5, 0., 319.5, 0., 1454.5, 239.5, 0., 0., 1. ]\n";
  const std::string cut = head + "camera_matrix: !!opencv-matrix\n   rows: 3\n";
  for (const std::string& text : {rows2, cut}) {
    std::ofstream((dir / "m.yml").string()) << text;
    try {
      ReadCameraFile((dir / "m.yml").string());
      FAIL() << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "camera_matrix") << e.what();
      EXPECT_EQ(std::string(e.what()).find("OpenCV("), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find("total()"), std::string::npos) << e.what();
    }
  }
}

TEST(CameraCalibration, AnImageTooSmallForTheBoardNamesTheImage) {
  const std::vector<std::pair<std::string, cv::Mat>> images{{"1px.png", cv::Mat(1, 1, CV_8U, cv::Scalar(128))}};
  try {
    CalibrateCamera(images, ChessboardSpec{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "1px.png");
    EXPECT_EQ(e.field(), "image size") << e.what();
  }
}

TEST(CameraCalibration, RecoversTheVirtualCameraFromRenderedChessboards) {
  CameraModel truth = CameraModel::ForField(480, 360, 110, 250, -0.08);
  VirtualCamera cam(truth);
  ChessboardSpec board;
  std::vector<std::pair<std::string, cv::Mat>> images;
  ImageDisturbances d;
  d.noise_grey = 1.0;
  int i = 0;
  for (const auto& [r, t] : CalibrationPoses(board, 250, 10))
    images.emplace_back("board" + std::to_string(i), cam.RenderChessboard(board.cols, board.rows, board.square_mm, r, t, d, i++));
  const auto res = CalibrateCamera(images, board);
  EXPECT_EQ(res.images_used, 10);
  EXPECT_LT(res.camera.rms_reprojection_px, 0.1);
  EXPECT_NEAR(res.camera.fx / truth.fx, 1.0, 2e-3);
  EXPECT_NEAR(res.camera.cx, truth.cx, 2.0);
  EXPECT_NEAR(res.camera.k1, truth.k1, 0.02);
  // Too few boards: a clear error.
  images.resize(2);
  EXPECT_THROW(CalibrateCamera(images, board), InputError);
}

TEST(VisionCli, BadImagesExitWithCode2AndTheFileName) {
  const fs::path dir = fs::temp_directory_path() / "trueaxis_vision_cli_test";
  fs::create_directories(dir);
  std::ofstream((dir / "empty.png").string()) << "";
  cv::imwrite((dir / "small.png").string(), cv::Mat(100, 120, CV_8U, cv::Scalar(90)));
  const std::string common = " --marker " + std::string(TRUEAXIS_SOURCE_DIR) + "/examples/vision/marker.toml --camera " +
                             std::string(TRUEAXIS_SOURCE_DIR) + "/examples/vision/camera.yml";
  auto r = trueaxis::testing::RunCli("vision measure " + (dir / "empty.png").string() + common);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("empty.png"), std::string::npos) << r.output;
  r = trueaxis::testing::RunCli("vision measure " + (dir / "small.png").string() + common);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("120×100"), std::string::npos) << r.output;
  // A header claiming 100000×100000 px: exit 2 naming the file, not OpenCV's assertion with exit 1.
  trueaxis::testing::WritePngBomb((dir / "bomb.png").string());
  for (const std::string& sub : {std::string("measure "), "reference --out " + (dir / "ref.toml").string() + " "}) {
    r = trueaxis::testing::RunCli("vision " + sub + (dir / "bomb.png").string() + common);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("bomb.png: field 'image'"), std::string::npos) << r.output;
  }
  r = trueaxis::testing::RunCli("vision run --hours 1 --interval-s 600 --disturb fog" + common);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--disturb"), std::string::npos) << r.output;
}

TEST(VisionCli, SixFramesWithoutAMarkerRaiseTheAlarm) {
  const fs::path dir = fs::temp_directory_path() / "trueaxis_vision_cli_alarm";
  fs::create_directories(dir);
  std::string files;
  for (int i = 0; i < 6; ++i) {
    const auto p = dir / ("grey" + std::to_string(i) + ".png");
    cv::imwrite(p.string(), cv::Mat(480, 640, CV_8U, cv::Scalar(100 + i)));
    files += " " + p.string();
  }
  const auto alarm = (dir / "alarm.json").string();
  const auto r = trueaxis::testing::RunCli("vision measure" + files + " --marker " + std::string(TRUEAXIS_SOURCE_DIR) +
                                           "/examples/vision/marker.toml --camera " + std::string(TRUEAXIS_SOURCE_DIR) +
                                           "/examples/vision/camera.yml --alarm-out " + alarm);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("ALARM"), std::string::npos) << r.output;
  std::ifstream f(alarm);
  const std::string json((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"feed_hold\": true"), std::string::npos) << json;
}

}  // namespace
}  // namespace trueaxis::vision

namespace trueaxis::vision {
namespace {

TEST(VisionCli, RunWritesAReportWithExampleFramesAndTheTruth) {
  const auto dir = std::filesystem::temp_directory_path() / "trueaxis_vision_cli_report";
  std::filesystem::create_directories(dir);
  const auto html = (dir / "run.html").string(), csv = (dir / "run.csv").string();
  const auto r = trueaxis::testing::RunCli("vision run --hours 1 --interval-s 900 --disturb chips --marker " +
                                           std::string(TRUEAXIS_SOURCE_DIR) + "/examples/vision/marker.toml --camera " +
                                           std::string(TRUEAXIS_SOURCE_DIR) + "/examples/vision/camera.yml --report " +
                                           html + " --csv " + csv + " --machine " + std::string(TRUEAXIS_SOURCE_DIR) +
                                           "/examples/machines/vmc850.toml");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream f(html);
  const std::string page((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(page.find("truth (virtual spindle)"), std::string::npos);
  std::ifstream c(csv);
  std::string header;
  std::getline(c, header);
  EXPECT_NE(header.find("true_growth_um"), std::string::npos);
  int rows = 0;
  for (std::string line; std::getline(c, line);) ++rows;
  EXPECT_EQ(rows, 5);  // 0, 15, 30, 45, 60 min
}

}  // namespace
}  // namespace trueaxis::vision
