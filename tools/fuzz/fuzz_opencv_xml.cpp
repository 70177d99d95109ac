// OpenCV FileStorage XML (pipeline/opencv_yaml.h: OpenCvYaml::Parse of an XML text).
#include "fuzz_common.h"
#include "pipeline/opencv_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lt::fuzz::ExpectCleanErrors([&] {
    const lt::OpenCvYaml y = lt::OpenCvYaml::Parse(lt::fuzz::Text(data, size), "calib.xml");
    for (const auto& e : y.entries()) {
      lt::fuzz::ExpectCleanErrors([&] { y.Number(e); });
      lt::fuzz::ExpectCleanErrors([&] { y.String(e); });
      lt::fuzz::ExpectCleanErrors([&] {
        const lt::YamlMatrix& m = y.Matrix(e);
        if (m.rows > 0 && m.cols > 0) (void)m.At(m.rows - 1, m.cols - 1);
      });
    }
  });
  return 0;
}
