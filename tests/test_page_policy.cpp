// The huge-page policy (util/page_policy.h): the GLINT_HUGE_PAGES values,
// and free page reporting read from a made-up sysfs tree.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "glint/util/page_policy.h"

namespace fs = std::filesystem;
using glint::HugePagePolicy;

TEST(HugePagePolicy, ReadsTheEnvironmentValue) {
  EXPECT_EQ(glint::huge_page_policy(nullptr), HugePagePolicy::automatic);
  EXPECT_EQ(glint::huge_page_policy(""), HugePagePolicy::automatic);
  EXPECT_EQ(glint::huge_page_policy("1"), HugePagePolicy::always);
  EXPECT_EQ(glint::huge_page_policy("always"), HugePagePolicy::always);
  EXPECT_EQ(glint::huge_page_policy("0"), HugePagePolicy::never);
  EXPECT_EQ(glint::huge_page_policy("never"), HugePagePolicy::never);
  EXPECT_EQ(glint::huge_page_policy("madvise"), HugePagePolicy::automatic);
}

namespace {

// A directory laid out as /sys/bus/virtio/devices, removed at the end.
class FakeVirtioDevices {
 public:
  FakeVirtioDevices()
      : root_(fs::path(::testing::TempDir()) / ("glint-virtio-" + std::to_string(::getpid()) + "-" +
                                                ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  ~FakeVirtioDevices() { fs::remove_all(root_); }
  void add(int index, const std::string& device_id, const std::string& features) const {
    const fs::path dir = root_ / ("virtio" + std::to_string(index));
    fs::create_directories(dir);
    std::ofstream(dir / "device") << device_id << "\n";
    std::ofstream(dir / "features") << features << "\n";
  }
  std::string path() const { return root_.string(); }

 private:
  fs::path root_;
};

// Feature strings as sysfs writes them: one character a bit, bit 0 first.
std::string features_with(int bit) {
  std::string f(64, '0');
  f[bit] = '1';
  return f;
}

}  // namespace

TEST(HugePagePolicy, FindsABalloonThatReportsFreePages) {
  const FakeVirtioDevices devices;
  devices.add(0, "0x0002", features_with(5));  // a block device: its bit 5 means something else
  devices.add(1, "0x0005", features_with(1));  // a balloon without reporting
  EXPECT_FALSE(glint::reports_free_pages(devices.path().c_str()));
  devices.add(7, "0x0005", features_with(5));  // numbering need not be contiguous
  EXPECT_TRUE(glint::reports_free_pages(devices.path().c_str()));
}

TEST(HugePagePolicy, NoVirtioDevicesMeansNoReporting) {
  const FakeVirtioDevices devices;
  EXPECT_FALSE(glint::reports_free_pages(devices.path().c_str()));
  EXPECT_FALSE(glint::reports_free_pages((devices.path() + "/missing").c_str()));
  devices.add(0, "0x0005", "01");  // too short to hold bit 5
  EXPECT_FALSE(glint::reports_free_pages(devices.path().c_str()));
}

// The process's answer follows the environment when it names a policy (the
// test command sets none, so only its consistency is checked then).
TEST(HugePagePolicy, TheProcessAnswerIsStable) {
  const bool first = glint::huge_pages_pay();
  EXPECT_EQ(glint::huge_pages_pay(), first);
  switch (glint::huge_page_policy(std::getenv("GLINT_HUGE_PAGES"))) {
    case HugePagePolicy::always:
      EXPECT_TRUE(first);
      break;
    case HugePagePolicy::never:
      EXPECT_FALSE(first);
      break;
    case HugePagePolicy::automatic:
#if defined(__linux__)
      EXPECT_EQ(first, !glint::reports_free_pages());
#else
      EXPECT_FALSE(first);  // no madvise to ask
#endif
      break;
  }
}
