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

TEST_CASE("check --format json: 'too many errors' is the file's last diagnostic, without a position",
          "[cli][check]") {
    TempDir dir;
    std::string text;
    for (int i = 0; i < 30; ++i)
        text += "let a" + std::to_string(i) + " = undefined_" + std::to_string(i) + "\n";
    write_file(dir / "many.wsdi", text);
    const RunResult plain = run_wsd(dir, "check many.wsdi");
    REQUIRE(plain.err.find("error: too many errors, stopping") != std::string::npos);
    const RunResult r = run_wsd(dir, "check --format json many.wsdi");
    CHECK(r.status == plain.status);
    CHECK(r.err.empty());
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j.size() == 1);
    const nlohmann::json& last = j[0]["diagnostics"].back();
    CHECK(last["severity"] == "error");
    CHECK(last["message"] == "too many errors, stopping");
    CHECK(last["file"] == "many.wsdi");
    CHECK(last["line"].is_null());
    CHECK(last["end_column"].is_null());
}

TEST_CASE("check --format json: an unused --define is a warning in the JSON, not text on stderr",
          "[cli][check]") {
    TempDir dir;
    write_file(dir / "ok.wsdi", "let a = param(\"used\", 1)\n");
    const RunResult r = run_wsd(dir, "check --format json -D zz=1 -D used=2 ok.wsdi");
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    const nlohmann::json j = nlohmann::json::parse(r.out);
    REQUIRE(j.size() == 1);
    CHECK(j[0]["ok"] == true);
    REQUIRE(j[0]["diagnostics"].size() == 1);
    const nlohmann::json& d = j[0]["diagnostics"][0];
    CHECK(d["severity"] == "warning");
    CHECK(d["message"] == "--define zz was not used: no param(\"zz\", ...) call read it");
    CHECK(d["file"] == "ok.wsdi");
    CHECK(d["line"].is_null());
    const RunResult quiet = run_wsd(dir, "check --format json --no-warnings -D zz=1 ok.wsdi");
    CHECK(quiet.err.empty());
    CHECK(nlohmann::json::parse(quiet.out)[0]["diagnostics"].empty());
}
