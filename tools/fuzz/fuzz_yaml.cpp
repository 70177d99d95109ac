// The YAML tree (pipeline/yaml_tree.h) and what reads it: the camera files of
// other tools (ROS, Kalibr, camodocal, VINS-Fusion) and OpenCV's FileStorage YAML.
#include "fuzz_common.h"
#include "pipeline/calibration_file.h"
#include "pipeline/camera_file_formats.h"
#include "pipeline/opencv_yaml.h"
#include "pipeline/yaml_tree.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lt::fuzz::ExpectCleanErrors([&] {
    lt::YamlLine first;
    const lt::YamlNode root = lt::ParseYamlTree(lt::fuzz::Text(data, size), "calib.yaml", &first);
    lt::CalibrationFile other;
    if (lt::ReadOtherCameraFile(root, "calib.yaml", std::nullopt, &other)) return;
    const lt::OpenCvYaml y = lt::OpenCvYaml::Parse(root, first, "calib.yaml");
    for (const auto& e : y.entries()) {
      lt::fuzz::ExpectCleanErrors([&] { y.Number(e); });
      lt::fuzz::ExpectCleanErrors([&] { y.Integer(e, -1000000, 1000000); });
      lt::fuzz::ExpectCleanErrors([&] { y.String(e); });
      lt::fuzz::ExpectCleanErrors([&] {
        const lt::YamlMatrix& m = y.Matrix(e);
        double sum = 0;
        for (int r = 0; r < m.rows; ++r)
          for (int c = 0; c < m.cols; ++c) sum += m.At(r, c);
        (void)sum;
      });
    }
  });
  return 0;
}
