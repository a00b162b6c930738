// The golden model must be independent of the kernels: it may include nothing from kernels/
// except the shared type header parallax/kernels/params.hpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

TEST(Isolation, ReferenceIncludesOnlyTheKernelParamsHeader) {
  const std::filesystem::path root(PARALLAX_REFERENCE_SOURCE_DIR);
  ASSERT_TRUE(std::filesystem::is_directory(root)) << root;
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cpp" && ext != ".hpp" && ext != ".h") continue;
    ++files;
    std::ifstream in(entry.path());
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      if (line.find("#include") == std::string::npos) continue;
      if (line.find("kernels") == std::string::npos) continue;
      EXPECT_NE(line.find("\"parallax/kernels/params.hpp\""), std::string::npos)
          << entry.path() << ":" << line_no << ": " << line;
    }
  }
  EXPECT_GE(files, 2);
}

}  // namespace
