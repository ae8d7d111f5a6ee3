// `wsd check --format json` through the real binary, on inputs the JSON must survive: file names
// that are not UTF-8, and the diagnostics the text form prints outside the scene's own.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "app_test_util.h"

using namespace wsd::test;

TEST_CASE("check --format json: a file name that is not UTF-8 is still valid JSON", "[cli][check]") {
    TempDir dir;
    const std::string name = "x\xff.wsdi";
    write_file(dir / name, "let a = 1\n");
    const RunResult r = run_wsd(dir, "check --format json " + shell_quote(name));
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j.size() == 1);
    CHECK(j[0]["file"] == "x\xef\xbf\xbd.wsdi");  // the stray byte as U+FFFD
    CHECK(j[0]["ok"] == true);
}
