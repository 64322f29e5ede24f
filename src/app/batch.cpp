#include "jade/app/batch.h"

#include "jade/core/display.h"
#include "jade/core/error.h"
#include "jade/io/atomic_file.h"
#include "jade/io/image_io.h"
#include "jade/io/text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace jade {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The manifest's entries are the pipeline's: a word that names a command
// would turn an entry into that command.
constexpr const char* kCommands[] = {"volume", "render", "merge", "bench", "batch", "summary"};

std::string resolved(const std::string& path, const fs::path& base) {
    if (path.empty() || fs::path(path).is_absolute()) return path;
    return (base / path).lexically_normal().string();
}

std::vector<std::string> split_words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    for (char ch : line) {
        if (ch == ',') {
            cells.push_back(cell);
            cell.clear();
        } else if (ch != '\r') {
            cell += ch;
        }
    }
    cells.push_back(cell);
    return cells;
}

BatchManifest read_csv_manifest(const std::string& path, std::istream& in) {
    BatchManifest m;
    std::string line;
    if (!std::getline(in, line) || split_csv_line(line) != std::vector<std::string>{"photo", "mask", "mesh", "out", "flags"})
        fail_file(path, "a CSV manifest begins with the header photo,mask,mesh,out,flags");
    for (int row = 2; std::getline(in, line); ++row) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const std::vector<std::string> c = split_csv_line(line);
        if (c.size() != 5) fail_file(path, "line " + std::to_string(row) + " has " + std::to_string(c.size()) +
                                               " cells, not 5 (photo,mask,mesh,out,flags; no quoting)");
        m.entries.push_back({c[0], c[1], c[2], c[3], split_words(c[4])});
    }
    return m;
}

BatchManifest read_json_manifest(const std::string& path, std::istream& in) {
    BatchManifest m;
    try {
        const json j = json::parse(in);
        m.flags = j.value("flags", std::vector<std::string>{});
        for (const json& e : j.at("entries"))
            m.entries.push_back({e.value("photo", ""), e.value("mask", ""), e.value("mesh", ""), e.value("out", ""),
                                 e.value("flags", std::vector<std::string>{})});
    } catch (const json::exception& e) {
        fail_file(path, std::string("not a manifest ({\"entries\": [{\"photo\", \"mesh\", ...}]}): ") + e.what());
    }
    return m;
}

void check_entry(const std::string& path, const BatchEntry& e, std::size_t index) {
    const std::string where = "entry " + std::to_string(index) + ": ";
    if (e.photo.empty() || e.mesh.empty()) fail_file(path, where + "names no photo or no mesh");
    for (const std::string& f : e.flags)
        for (const char* c : kCommands)
            if (f == c) fail_file(path, where + "flag '" + f + "' names a command; an entry is a fit's flags");
}

}  // namespace

BatchManifest load_manifest(const std::string& path) {
    std::ifstream in(path);
    if (!in) fail_file(path, "no such file, or it cannot be read");
    const std::string ext = fs::path(path).extension().string();
    BatchManifest m = ext == ".csv" ? read_csv_manifest(path, in) : read_json_manifest(path, in);
    if (m.entries.empty()) fail_file(path, "the manifest has no entries");
    m.file = path;
    const fs::path base = fs::path(path).parent_path();
    for (std::size_t i = 0; i < m.entries.size(); ++i) {
        BatchEntry& e = m.entries[i];
        check_entry(path, e, i);
        if (e.out.empty()) e.out = fs::path(e.photo).stem().string() + "-" + fs::path(e.mesh).stem().string();
        for (std::string* p : {&e.photo, &e.mask, &e.mesh, &e.out}) *p = resolved(*p, base);
    }
    for (const std::string& f : m.flags)
        for (const char* c : kCommands)
            if (f == c) fail_file(path, "common flag '" + f + "' names a command");
    return m;
}

std::vector<std::string> entry_arguments(const BatchManifest& m, int index) {
    if (index < 0 || index >= int(m.entries.size()))
        throw Error("--index " + std::to_string(index) + " is not an entry of " + m.file + " (0 to " +
                    std::to_string(m.entries.size() - 1) + ")");
    const BatchEntry& e = m.entries[std::size_t(index)];
    std::vector<std::string> args = {"--photo", e.photo, "--mesh", e.mesh, "--out", e.out};
    if (!e.mask.empty()) args.insert(args.end(), {"--mask", e.mask});
    args.insert(args.end(), m.flags.begin(), m.flags.end());
    args.insert(args.end(), e.flags.begin(), e.flags.end());
    return args;
}

void create_entry_parent(const BatchManifest& m, int index) {
    entry_arguments(m, index);  // checks the index
    const fs::path parent = fs::path(m.entries[std::size_t(index)].out).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::create_directories(parent, ec) && ec)
        fail_file(parent.string(), "cannot create the folder: " + ec.message());
}

namespace {

// A value of the report at a JSON pointer, as CSV text ("" when absent).
std::string cell(const json& report, const std::string& pointer) {
    const json::json_pointer p(pointer);
    if (!report.contains(p)) return "";
    const json& v = report.at(p);
    if (v.is_string()) return v.get<std::string>();
    if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
    if (v.is_number()) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
        return buf;
    }
    return "";
}

// The summary's columns: name, then where report.json holds it.
struct Column {
    std::string name, pointer;
};
std::vector<Column> summary_columns() {
    std::vector<Column> c = {{"converged", "/fit/converged"}, {"fit", "/fit/method"}, {"renders", "/fit/renders"},
                             {"exposure", "/fit/exposure"}};
    const char* rgb[3] = {"r", "g", "b"};
    for (const auto& [name, pointer] : std::vector<std::pair<std::string, std::string>>{
             {"ks", "/fit/ks"}, {"contrast", "/fit/contrast"}, {"A_photo", "/appearance/A_photo"},
             {"A_render", "/appearance/A_render"}, {"S_photo", "/appearance/S_photo"},
             {"S_render", "/appearance/S_render"}, {"D", "/appearance/D"}})
        for (int k = 0; k < 3; ++k) c.push_back({name + "_" + rgb[k], pointer + "/" + std::to_string(k)});
    c.insert(c.end(), {{"structure_distance", "/appearance/structure_distance"},
                       {"structure_distance_error", "/appearance/structure_distance_error"},
                       {"final_error", "/final_render/estimated_relative_error"},
                       {"final_spp", "/final_render/spp"},
                       {"seconds", "/seconds/total"},
                       {"peak_memory_bytes", "/peak_memory_bytes"}});
    return c;
}

}  // namespace

BatchSummary write_batch_summary(const BatchManifest& m, const std::string& csv_path) {
    const std::vector<Column> columns = summary_columns();
    std::string text = "index,photo,mesh,out,status";
    for (const Column& c : columns) text += "," + c.name;
    text += "\n";
    BatchSummary summary;
    for (std::size_t i = 0; i < m.entries.size(); ++i) {
        const BatchEntry& e = m.entries[i];
        text += std::to_string(i) + "," + e.photo + "," + e.mesh + "," + e.out;
        std::ifstream in((fs::path(e.out) / "report.json").string());
        json report;
        std::string status = "missing";
        if (in) {
            try {
                report = json::parse(in);
                status = "done";
            } catch (const json::exception&) {
                status = "unreadable";
            }
        }
        (status == "done" ? summary.done : summary.missing) += 1;
        text += "," + status;
        for (const Column& c : columns) text += "," + (status == "done" ? cell(report, c.pointer) : "");
        text += "\n";
    }
    write_text_file(csv_path, text);
    return summary;
}

void write_contact_sheet(const BatchManifest& m, const std::string& png_path, int tile_width) {
    const int n = int(m.entries.size());
    const int columns = int(std::ceil(std::sqrt(double(n))));
    const int rows = (n + columns - 1) / columns;
    std::vector<ImageF32> tiles;
    int tile_height = 1;
    for (const BatchEntry& e : m.entries) {
        const std::string file = (fs::path(e.out) / "compare.png").string();
        ImageF32 tile;
        if (fs::exists(file)) {
            const ImageF32 img = read_image_f32(file);
            const int h = std::max(1, int(std::lround(double(img.height) * tile_width / img.width)));
            tile = resize_image(img, tile_width, h);
            tile_height = std::max(tile_height, h);
        }
        tiles.push_back(std::move(tile));
    }
    constexpr int kGap = 4, kLabel = 20, kTextSize = 14;
    const int cell_height = kLabel + tile_height;
    RgbImage8 sheet{columns * tile_width + (columns + 1) * kGap, rows * cell_height + (rows + 1) * kGap, {}};
    sheet.pixels.assign(std::size_t(sheet.width) * sheet.height * 3, 255);
    for (int k = 0; k < n; ++k) {
        const int ox = kGap + (k % columns) * (tile_width + kGap), oy = kGap + (k / columns) * (cell_height + kGap);
        const ImageF32& t = tiles[std::size_t(k)];
        const std::string label = "#" + std::to_string(k) + "  " + fs::path(m.entries[std::size_t(k)].out).filename().string() +
                                  (t.width == 0 ? "  (no compare.png)" : "");
        draw_text(sheet, ox + 2, oy + kLabel - 5, label, kTextSize, Rgb8{0, 0, 0});
        for (int y = 0; y < tile_height; ++y)
            for (int x = 0; x < tile_width; ++x)
                for (int c = 0; c < 3; ++c) {
                    // Grey where an entry has no compare.png; white below a shorter tile.
                    const double v = t.width == 0 ? 0.2 : y < t.height ? t.at(x, y, std::min(c, t.channels - 1)) : 1.0;
                    sheet.pixels[(std::size_t(oy + kLabel + y) * sheet.width + ox + x) * 3 + c] = display_level(v);
                }
    }
    write_image_u8(png_path, sheet.width, sheet.height, 3, sheet.pixels);
}

}  // namespace jade
