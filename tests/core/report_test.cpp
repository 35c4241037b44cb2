#include <gtest/gtest.h>

#include <sstream>
#include <thread>
#include <vector>

#include "core/progress.h"
#include "core/stats.h"

using namespace littoral;

// Non-terminal progress output (CI, redirected stderr): one line per 10% step plus a final line
// with the count and rate; never more lines than that, whatever the number of advance() calls.
TEST(Progress, PlainLinesWhenNotATerminal) {
    testing::internal::CaptureStderr();
    {
        Progress p("tracing", 1000, "rows");
        for (int i = 0; i < 1000; ++i) p.advance();
    }
    const std::string out = testing::internal::GetCapturedStderr();
    int lines = 0;
    for (char c : out) lines += c == '\n';
    EXPECT_EQ(lines, 10) << out;  // 10%, ..., 90% and the final summary
    EXPECT_NE(out.find("tracing:  50% (500/1000 rows)"), std::string::npos) << out;
    EXPECT_NE(out.find("tracing: 1000 rows in"), std::string::npos) << out;
}

TEST(Progress, DisabledPrintsNothing) {
    Progress::setEnabled(false);
    testing::internal::CaptureStderr();
    {
        Progress p("quiet", 10);
        p.advance(10);
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    Progress::setEnabled(true);
}

// Counters are exact under concurrent increments (4 threads x 100000 adds = 400000).
TEST(Stats, ConcurrentCountersAreExact) {
    statsReset();
    StatCounter& c = statCounter("test: rays cast");
    std::vector<std::thread> ts;
    for (int t = 0; t < 4; ++t)
        ts.emplace_back([&] {
            for (int i = 0; i < 100000; ++i) c.add();
        });
    for (auto& t : ts) t.join();
    EXPECT_EQ(c.value.load(), 400000);
    EXPECT_EQ(&statCounter("test: rays cast"), &c);
    std::ostringstream os;
    statsPrint(os);
    EXPECT_NE(os.str().find("test: rays cast"), std::string::npos);
    EXPECT_NE(os.str().find("400000"), std::string::npos);
}

#include "core/log.h"

// The same warning text is printed once per process; a different text is printed.
TEST(Log, WarnOncePrintsEachTextOnce) {
    testing::internal::CaptureStderr();
    log::warnOnce("grid {} m is small", 60);
    log::warnOnce("grid {} m is small", 60);
    log::warnOnce("grid {} m is small", 70);
    const std::string out = testing::internal::GetCapturedStderr();
    EXPECT_EQ(out, "warning: grid 60 m is small\nwarning: grid 70 m is small\n");
}
