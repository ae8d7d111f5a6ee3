// `wsd bench --quick` through the real binary on a tiny scene built for it (fine detail that
// supersampling resolves, an area light, a mirror): every sweep row is in bench.csv, errors are
// non-negative and fall as supersamples rise, and bench.svg is balanced XML with one path per knob.
#include <catch2/catch.hpp>
#include <map>
#include <sstream>

#include "app_test_util.h"

using namespace wsd::test;

namespace {

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::istringstream cells_in(line);
        std::string cell;
        while (std::getline(cells_in, cell, ',')) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

size_t count_tags(const std::string& xml, const std::string& name) {
    size_t n = 0;
    for (size_t at = xml.find("<" + name + " "); at != std::string::npos;
         at = xml.find("<" + name + " ", at + 1))
        ++n;
    return n;
}

bool balanced(const std::string& xml) {
    std::vector<std::string> stack;
    size_t pos = 0;
    while ((pos = xml.find('<', pos)) != std::string::npos) {
        const size_t end = xml.find('>', pos);
        if (end == std::string::npos) return false;
        const std::string tag = xml.substr(pos + 1, end - pos - 1);
        pos = end + 1;
        if (tag.empty() || tag[0] == '?' || tag[0] == '!') continue;
        if (tag[0] == '/') {
            if (stack.empty() || stack.back() != tag.substr(1)) return false;
            stack.pop_back();
        } else if (tag.back() != '/') {
            stack.push_back(tag.substr(0, tag.find_first_of(" \n")));
        }
    }
    return stack.empty();
}

}  // namespace

TEST_CASE("bench --quick sweeps every knob and writes csv, md and svg", "[bench]") {
    TempDir dir;
    // A high-frequency checker seen at a grazing angle: one sample per pixel aliases badly.
    write_file(
        dir / "b.wsd",
        "settings { width 16  height 12  supersamples 1  max_depth 3  seed 11 }\n"
        "camera { position <0, 1, -5>  look_at <0, 0.4, 0>  fov 45 }\n"
        "light area { position <1, 4, -2>  u <1.5, 0, 0>  v <0, 0, 1.5>  samples 2 }\n"
        "plane { normal <0, 1, 0>  distance 0  material { texture checker { scale 0.13 } } }\n"
        "sphere { center <0.6, 0.5, 0.5>  radius 0.5  material { color <0.8, 0.8, 0.8>  reflection 0.6 } }\n"
        "box { min <-1.4, 0, 0>  max <-0.6, 0.9, 0.8>  material { color <0.2, 0.5, 0.9> } }\n"
        // Reflection 0.1: below a bailout of 1/8, above 1/512.
        "sphere { center <-0.1, 0.35, -0.9>  radius 0.35  material { color <0.9, 0.3, 0.2>  reflection 0.1 } "
        "}\n");
    const RunResult r = run_wsd(dir, "bench b.wsd --quick -o out --reference-light-samples 4 --threads 2");
    REQUIRE(r.status == 0);
    CHECK(r.out.find("supersamples") != std::string::npos);  // the table
    {
        // Every row's columns end where the header's do, the longest knob name included.
        std::istringstream table(r.out);
        std::string header, line;
        REQUIRE(std::getline(table, header));
        const size_t ssim_end = header.find("SSIM") + 4;
        bool longest = false;
        while (std::getline(table, line) && !line.empty()) {
            longest = longest || line.rfind("exact_area_lights", 0) == 0;
            if (line.ends_with(" *"))
                line.resize(line.size() - 2);
            else if (line.ends_with(' '))
                line.pop_back();
            CHECK(line.size() == ssim_end);
        }
        CHECK(longest);
    }
    CHECK_FALSE(r.err.empty());  // progress

    const auto rows = parse_csv(read_file(dir / "out/bench.csv"));
    REQUIRE(rows.size() > 1);
    const std::vector<std::string>& header = rows[0];
    std::map<std::string, size_t> col;
    for (size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
    for (const char* name : {"knob", "value", "wall_seconds", "cpu_seconds", "camera_rays", "shadow_rays",
                             "reflection_rays", "refraction_rays", "rmse", "psnr", "ssim"})
        REQUIRE(col.count(name));

    std::map<std::string, std::vector<std::string>> values;
    std::map<std::string, double> rmse, secondary;
    for (size_t i = 1; i < rows.size(); ++i) {
        const auto& row = rows[i];
        REQUIRE(row.size() == header.size());
        values[row[col["knob"]]].push_back(row[col["value"]]);
        const double e = std::stod(row[col["rmse"]]);
        CHECK(e >= 0);
        CHECK(std::stod(row[col["wall_seconds"]]) >= 0);
        CHECK(std::stod(row[col["cpu_seconds"]]) >= 0);
        CHECK(std::stod(row[col["ssim"]]) <= 1.0);
        rmse[row[col["knob"]] + "=" + row[col["value"]]] = e;
        secondary[row[col["knob"]] + "=" + row[col["value"]]] =
            std::stod(row[col["reflection_rays"]]) + std::stod(row[col["refraction_rays"]]);
    }
    CHECK(values["supersamples"] == std::vector<std::string>{"1", "4", "16"});
    // Progressive rows carry their own estimate; the others a dash.
    REQUIRE(col.count("estimated_rmse"));
    CHECK(values["target_error"] == std::vector<std::string>{"0.04", "0.02"});
    for (size_t i = 1; i < rows.size(); ++i) {
        const std::string& estimate = rows[i][col["estimated_rmse"]];
        if (rows[i][col["knob"]] != "target_error") {
            CHECK(estimate == "-");
            continue;
        }
        const double target = std::stod(rows[i][col["value"]]);
        CHECK(std::stod(estimate) > 0);
        CHECK(std::stod(estimate) <= 1.5 * target);
    }
    CHECK(values["light_samples"] == std::vector<std::string>{"1", "4", "16"});
    CHECK(values["max_depth"] == std::vector<std::string>{"0", "1", "2"});
    CHECK(values["adaptive_aa"] == std::vector<std::string>{"off", "on"});
    CHECK(values["adaptive_lights"] == std::vector<std::string>{"off", "on"});
    CHECK(values["exact_area_lights"] == std::vector<std::string>{"off", "on"});
    CHECK(values["bailout"] == std::vector<std::string>{"0", "1/512", "1/8"});
    CHECK(values.size() == 8);
    // A higher bailout traces fewer secondary rays, never more.
    CHECK(secondary["bailout=0"] >= secondary["bailout=1/512"]);
    CHECK(secondary["bailout=1/512"] >= secondary["bailout=1/8"]);
    CHECK(secondary["bailout=0"] > secondary["bailout=1/8"]);
    CHECK(rmse["supersamples=1"] > rmse["supersamples=4"]);
    CHECK(rmse["supersamples=4"] > rmse["supersamples=16"]);
    // Depth 0 drops the mirror's reflection entirely; depth 2 is far closer.
    CHECK(rmse["max_depth=0"] > rmse["max_depth=2"]);

    const std::string md = read_file(dir / "out/bench.md");
    CHECK(md.find("| supersamples | 16 |") != std::string::npos);
    CHECK(md.find("reference") != std::string::npos);

    const std::string svg = read_file(dir / "out/bench.svg");
    CHECK(balanced(svg));
    CHECK(count_tags(svg, "path") == 8);
    for (const char* knob : {"supersamples", "light_samples", "max_depth", "adaptive_aa", "adaptive_lights",
                             "exact_area_lights", "bailout", "target_error"})
        CHECK(svg.find(std::string(">") + knob + "</text>") != std::string::npos);  // legend
    CHECK(svg.find("Pareto") != std::string::npos);
}

TEST_CASE("bench failures: unreadable scene 3, scene error 1, missing parent directory 3", "[bench]") {
    TempDir dir;
    write_file(dir / "bad.wsd", "camera { }\n");
    write_file(dir / "s.wsd", tiny_scene());
    CHECK(run_wsd(dir, "bench nothing.wsd --quick").status == 3);
    CHECK(run_wsd(dir, "bench bad.wsd --quick").status == 1);
    CHECK(run_wsd(dir, "bench s.wsd --quick -o no/such/dir").status == 3);
    write_file(dir / "file", "x");
    const RunResult onto_file = run_wsd(dir, "bench s.wsd --quick -o file");
    CHECK(onto_file.status == 3);
    CHECK(onto_file.err.find("'file' as the output directory: it exists and is not a directory") !=
          std::string::npos);
    CHECK(run_wsd(dir, "bench s.wsd --quick --repeat 0").status == 2);
}
