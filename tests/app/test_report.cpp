// fit.csv as a reader parses it: one header, one row per fitting render,
// the columns in the header's order.
#include "jade/app/report.h"

#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <vector>

using namespace jade;

namespace {

std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
    return out;
}

}  // namespace

TEST_CASE("fit.csv: A at the final size beside the fitting render's own A, -1 where none was rendered",
          "[report]") {
    FitRecord judged;
    judged.iteration = 3;
    judged.a_render = {190.0, 150.0, 120.0};
    judged.a_final_size = {187.5, 146.25, 111.0};
    const FitRecord plain;  // a render of the k_s search: nothing at the final size
    std::stringstream csv(fit_csv({judged, plain}));
    std::string header, first, second;
    std::getline(csv, header);
    std::getline(csv, first);
    std::getline(csv, second);
    const std::vector<std::string> names = fields(header), a = fields(first), b = fields(second);
    REQUIRE(a.size() == names.size());
    REQUIRE(b.size() == names.size());
    const auto value = [&](const std::vector<std::string>& row, const std::string& name) {
        for (std::size_t i = 0; i < names.size(); ++i)
            if (names[i] == name) return std::stod(row[i]);
        FAIL("no column " << name);
        return 0.0;
    };
    CHECK(value(a, "A_render_b") == 120.0);
    CHECK(value(a, "A_final_size_r") == 187.5);
    CHECK(value(a, "A_final_size_g") == 146.25);
    CHECK(value(a, "A_final_size_b") == 111.0);
    CHECK(value(b, "A_final_size_b") == -1.0);
    CHECK(value(a, "iteration") == 3.0);
}

TEST_CASE("fit.csv: the structure distance and its error, the dominant orientation and its strength of the photo "
          "and of the render, on every row",
          "[report]") {
    FitRecord r;
    r.structure = 0.61;
    r.structure_error = 0.045;
    r.orientation_photo = 5.9;
    r.orientation_render = 135.3;
    r.strength_photo = 0.18;
    r.strength_render = 0.28;
    std::stringstream csv(fit_csv({r}));
    std::string header, row;
    std::getline(csv, header);
    std::getline(csv, row);
    const std::vector<std::string> names = fields(header), values = fields(row);
    REQUIRE(values.size() == names.size());
    std::vector<double> found;
    for (const char* name :
         {"structure", "structure_error", "orientation_photo", "orientation_render", "strength_photo", "strength_render"})
        for (std::size_t i = 0; i < names.size(); ++i)
            if (names[i] == name) found.push_back(std::stod(values[i]));
    CHECK(found == std::vector<double>{0.61, 0.045, 5.9, 135.3, 0.18, 0.28});
}
