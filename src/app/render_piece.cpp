#include "jade/app/render_piece.h"

#include "jade/core/error.h"
#include "jade/core/memory.h"
#include "jade/core/timing.h"
#include "jade/io/atomic_file.h"
#include "jade/io/exr_parts.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <filesystem>

namespace jade {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Format 2 added the strata's sums and format 3 the replicates' (render/film.h);
// format 1's pieces read as films of one stratum, and format 1's and 2's as
// films of one replicate.
constexpr int kPieceFormat = 3;
constexpr int kOtherStrata = Film::kStrata - 1;
constexpr int kOtherReplicates = Film::kReplicates - 1;
constexpr const char* kPieceAttribute = "jade:piece";
constexpr int kWords = 4;  // 32-bit words of a 128-bit sum
constexpr const char* kChannelNames[3] = {"R", "G", "B"};

// A whole non-negative decimal number, the whole text.
bool parse_count(const std::string& text, int& out) {
    if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos)
        return false;
    const long v = std::strtol(text.c_str(), nullptr, 10);
    if (v > INT_MAX) return false;
    out = int(v);
    return true;
}

// "a:b" as two counts.
bool parse_pair(const std::string& text, int& a, int& b) {
    const std::size_t colon = text.find(':');
    return colon != std::string::npos && parse_count(text.substr(0, colon), a) &&
           parse_count(text.substr(colon + 1), b);
}

std::string range_text(const PieceRange& r) {
    return "samples " + std::to_string(r.samples.first) + ":" + std::to_string(r.samples.last) + " of pixels " +
           std::to_string(r.pixels.x0) + ":" + std::to_string(r.pixels.x1) + "," + std::to_string(r.pixels.y0) +
           ":" + std::to_string(r.pixels.y1);
}

}  // namespace

SampleRange parse_sample_range(const std::string& text) {
    SampleRange r;
    if (!parse_pair(text, r.first, r.last) || r.last <= r.first)
        throw Error("--samples expects A:B with 0 <= A < B (samples A to B-1), not '" + text + "'");
    return r;
}

PixelBounds parse_pixel_bounds(const std::string& text) {
    PixelBounds b;
    const std::size_t comma = text.find(',');
    if (comma == std::string::npos || !parse_pair(text.substr(0, comma), b.x0, b.x1) ||
        !parse_pair(text.substr(comma + 1), b.y0, b.y1) || b.x1 <= b.x0 || b.y1 <= b.y0)
        throw Error("--pixels expects x0:x1,y0:y1 with x0 < x1 and y0 < y1 (columns x0 to x1-1, rows y0 to y1-1), "
                    "not '" + text + "'");
    return b;
}

PieceRange parse_piece_of(const std::string& text, const RenderJob& job) {
    const std::size_t slash = text.find('/');
    int index = 0, count = 0;
    if (slash == std::string::npos || !parse_count(text.substr(0, slash), index) ||
        !parse_count(text.substr(slash + 1), count) || count < 1 || index >= count)
        throw Error("--piece expects I/N with 0 <= I < N (piece I of N), not '" + text + "'");
    if (count > job.settings.spp)
        throw Error("--piece " + text + ": more pieces than the render's " + std::to_string(job.settings.spp) +
                    " samples (--spp)");
    const auto cut = [&](int i) { return int(std::int64_t(i) * job.settings.spp / count); };
    return {{cut(index), cut(index + 1)}, {0, 0, job.width, job.height}};
}

std::vector<std::string> split_piece_paths(const RenderJob& job, int count, const std::string& out) {
    std::vector<std::string> paths;
    for (int i = 0; i < count; ++i)
        paths.push_back(piece_path(out.empty() ? job.out : out,
                                   parse_piece_of(std::to_string(i) + "/" + std::to_string(count), job), job.width,
                                   job.height));
    return paths;
}

void validate_piece(const RenderJob& job, const PieceRange& r) {
    if (job.settings.time_limit > 0.0 || job.settings.target_error > 0.0)
        throw Error("a piece renders a fixed range of samples: --time and --target-error do not apply");
    if (r.samples.first < 0 || r.samples.last > job.settings.spp || r.samples.last <= r.samples.first)
        throw Error("--samples " + std::to_string(r.samples.first) + ":" + std::to_string(r.samples.last) +
                    " is not inside the render's samples 0:" + std::to_string(job.settings.spp) + " (--spp)");
    const PixelBounds& b = r.pixels;
    if (b.x0 < 0 || b.y0 < 0 || b.x1 > job.width || b.y1 > job.height || b.x1 <= b.x0 || b.y1 <= b.y0)
        throw Error("--pixels is not inside the " + std::to_string(job.width) + " x " + std::to_string(job.height) +
                    " image");
}

std::string piece_path(const std::string& out, const PieceRange& r, int width, int height) {
    std::string suffix = ".part-s" + std::to_string(r.samples.first) + "-" + std::to_string(r.samples.last);
    const PixelBounds& b = r.pixels;
    if (b.x0 != 0 || b.y0 != 0 || b.x1 != width || b.y1 != height)
        suffix += "-x" + std::to_string(b.x0) + "-" + std::to_string(b.x1) + "-y" + std::to_string(b.y0) + "-" +
                  std::to_string(b.y1);
    return sibling_path(out, suffix + ".exr");
}

namespace {

// The channel of stratum or replicate k (`part` names which): its sum's
// 32-bit word w of a colour channel, or (w < 0) its count.
std::string part_channel(const char* part, int k, const char* what, int w) {
    const std::string name = part + std::to_string(k) + "." + what;
    return w < 0 ? name : name + "." + std::to_string(w);
}

// The channels of parts 1 … `others` of a partition, in the order
// push_part_values writes them.
void push_part_channels(std::vector<std::string>& channels, const char* part, int others) {
    for (int k = 1; k <= others; ++k) {
        for (const char* c : kChannelNames)
            for (int w = 0; w < kWords; ++w) channels.push_back(part_channel(part, k, c, w));
        channels.push_back(part_channel(part, k, "count", -1));
    }
}

void push_part_values(std::vector<std::uint32_t>& out, const std::vector<__int128>& sums,
                      const std::vector<std::uint32_t>& counts, int others, std::size_t i) {
    for (int k = 0; k < others; ++k) {
        for (int c = 0; c < 3; ++c) {
            const auto u = static_cast<unsigned __int128>(sums[3 * (others * i + k) + c]);
            for (int w = 0; w < kWords; ++w) out.push_back(std::uint32_t(u >> (32 * w)));
        }
        out.push_back(counts[others * i + k]);
    }
}

// The piece's pixels as two EXR parts: a float preview and the exact sums.
std::vector<ExrPart> piece_parts(const Film& film, const PixelBounds& b, bool transparent) {
    ExrPart preview, sums;
    for (ExrPart* p : {&preview, &sums}) {
        p->full_width = film.width();
        p->full_height = film.height();
        p->x0 = b.x0;
        p->y0 = b.y0;
        p->width = b.x1 - b.x0;
        p->height = b.y1 - b.y0;
    }
    preview.name = "preview";
    preview.channels = {"R", "G", "B", "A"};
    sums.name = "sums";
    sums.integer = true;
    for (const char* kind : {"sum", "sumsq"})
        for (const char* c : kChannelNames)
            for (int w = 0; w < kWords; ++w)
                sums.channels.push_back(std::string(kind) + "." + c + "." + std::to_string(w));
    sums.channels.push_back("count");
    sums.channels.push_back("hits");
    push_part_channels(sums.channels, "stratum", kOtherStrata);
    push_part_channels(sums.channels, "replicate", kOtherReplicates);
    const std::vector<float> rgba = film.rgba(transparent);
    for (int y = b.y0; y < b.y1; ++y)
        for (int x = b.x0; x < b.x1; ++x) {
            const std::size_t i = std::size_t(y) * film.width() + x;
            preview.floats.insert(preview.floats.end(), rgba.begin() + 4 * i, rgba.begin() + 4 * i + 4);
            for (const auto* v : {&film.sums(), &film.sums_of_squares()})
                for (int c = 0; c < 3; ++c) {
                    const auto u = static_cast<unsigned __int128>((*v)[3 * i + c]);
                    for (int w = 0; w < kWords; ++w) sums.uints.push_back(std::uint32_t(u >> (32 * w)));
                }
            sums.uints.push_back(film.counts()[i]);
            sums.uints.push_back(film.object_hits()[i]);
            push_part_values(sums.uints, film.stratum_sums(), film.stratum_counts(), kOtherStrata, i);
            push_part_values(sums.uints, film.replicate_sums(), film.replicate_counts(), kOtherReplicates, i);
        }
    return {preview, sums};
}

}  // namespace

void write_render_piece(const std::string& path, const RenderJob& job, const PieceRange& r, const Film& film,
                        float exposure, double seconds) {
    const std::string folder = fs::path(path).parent_path().string();
    const json meta = {{"format", kPieceFormat},
                       {"samples", {r.samples.first, r.samples.last}},
                       {"pixels", {r.pixels.x0, r.pixels.y0, r.pixels.x1, r.pixels.y1}},
                       {"width", film.width()},
                       {"height", film.height()},
                       {"exposure", exposure},
                       {"seconds", seconds},
                       {"job", json::parse(job_json(job, folder.empty() ? "." : folder))}};
    std::vector<ExrPart> parts = piece_parts(film, r.pixels, job.transparent);
    parts[1].attributes.emplace_back(kPieceAttribute, meta.dump());
    write_exr_parts(path, parts);
}

namespace {

// Parts 1 … `others` of pixel i's partition from its channel values `px`,
// the channels' indices starting at `at` (push_part_channels' order).
void read_part_values(const std::uint32_t* px, const int* at, std::vector<__int128>& sums,
                      std::vector<std::uint32_t>& counts, int others, std::size_t i) {
    for (int k = 0; k < others; ++k, at += 3 * kWords + 1) {
        for (int c = 0; c < 3; ++c) {
            unsigned __int128 u = 0;
            for (int w = 0; w < kWords; ++w) u |= static_cast<unsigned __int128>(px[at[kWords * c + w]]) << (32 * w);
            sums[3 * (others * i + k) + c] = static_cast<__int128>(u);
        }
        counts[others * i + k] = px[at[3 * kWords]];
    }
}

// The film of a piece's "sums" part, checked against the piece's range.
Film piece_film(const std::string& path, const ExrPart& p, const PieceRange& r, int format) {
    std::vector<int> index;
    for (const char* kind : {"sum", "sumsq"})
        for (const char* c : kChannelNames)
            for (int w = 0; w < kWords; ++w)
                index.push_back(p.channel(std::string(kind) + "." + c + "." + std::to_string(w)));
    index.push_back(p.channel("count"));
    index.push_back(p.channel("hits"));
    const std::size_t strata_at = index.size();
    std::vector<std::string> parts;
    if (format >= 2) push_part_channels(parts, "stratum", kOtherStrata);
    const std::size_t replicates_at = strata_at + parts.size();
    if (format >= 3) push_part_channels(parts, "replicate", kOtherReplicates);
    for (const std::string& name : parts) index.push_back(p.channel(name));
    if (!p.integer || std::count(index.begin(), index.end(), -1) > 0)
        fail_file(path, "the piece's sums lack channels");
    const PixelBounds& b = r.pixels;
    if (p.x0 != b.x0 || p.y0 != b.y0 || p.width != b.x1 - b.x0 || p.height != b.y1 - b.y0)
        fail_file(path, "the piece's pixels disagree with its range");
    // The film the piece asks for must fit before anything is allocated for it.
    try {
        require_memory(2 * Film::memory_bytes(p.full_width, p.full_height), "its film");
    } catch (const Error& e) {
        fail_file(path, e.what());
    }
    Film::Sums s = Film::zero_sums(p.full_width, p.full_height);
    const std::size_t nc = p.channels.size();
    const std::uint32_t expected = std::uint32_t(r.samples.last - r.samples.first);
    for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
            const std::uint32_t* px = &p.uints[(std::size_t(y) * p.width + x) * nc];
            const std::size_t i = std::size_t(y + p.y0) * s.width + (x + p.x0);
            for (int k = 0; k < 6; ++k) {
                unsigned __int128 u = 0;
                for (int w = 0; w < kWords; ++w) u |= static_cast<unsigned __int128>(px[index[kWords * k + w]]) << (32 * w);
                (k < 3 ? s.sum : s.sum_sq)[3 * i + k % 3] = static_cast<__int128>(u);
            }
            s.count[i] = px[index[6 * kWords]];
            s.hits[i] = px[index[6 * kWords + 1]];
            if (format >= 2) read_part_values(px, &index[strata_at], s.stratum_sum, s.stratum_count, kOtherStrata, i);
            if (format >= 3)
                read_part_values(px, &index[replicates_at], s.replicate_sum, s.replicate_count, kOtherReplicates, i);
            if (s.count[i] != expected) fail_file(path, "a pixel's sample count disagrees with the piece's range");
        }
    try {
        return Film::from_sums(std::move(s));
    } catch (const Error& e) {
        fail_file(path, e.what());
    }
}

PieceRange read_range(const std::string& path, const json& meta) {
    PieceRange r;
    try {
        const auto s = meta.at("samples").get<std::array<int, 2>>();
        const auto b = meta.at("pixels").get<std::array<int, 4>>();
        r.samples = {s[0], s[1]};
        r.pixels = {b[0], b[1], b[2], b[3]};
    } catch (const json::exception&) {
        fail_file(path, "the piece's range is unreadable");
    }
    return r;
}

}  // namespace

RenderPiece read_render_piece(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) fail_file(path, "no such piece (not rendered yet, or rendered with flags beside --job: then name the pieces)");
    const std::vector<ExrPart> parts =
        read_exr_parts(path, 2, 6 * kWords + 2 + (kOtherStrata + kOtherReplicates) * (3 * kWords + 1) + 4);
    const ExrPart* sums = nullptr;
    for (const ExrPart& p : parts)
        if (p.name == "sums" && !p.attribute(kPieceAttribute).empty()) sums = &p;
    if (!sums) fail_file(path, "is not a piece of a jaderender render (no 'sums' part with jade:piece)");
    json meta;
    try {
        meta = json::parse(sums->attribute(kPieceAttribute));
    } catch (const json::exception&) {
        fail_file(path, "the piece's jade:piece attribute is not valid JSON");
    }
    const int format = meta.is_object() ? meta.value("format", 0) : 0;
    if (format < 1 || format > kPieceFormat)
        fail_file(path, "is a piece of an unknown format (this jaderender reads formats 1 to " +
                            std::to_string(kPieceFormat) + ")");
    RenderPiece piece;
    piece.file = path;
    piece.range = read_range(path, meta);
    if (!meta.contains("job") || !meta["job"].is_object()) fail_file(path, "the piece names no job");
    const std::string folder = fs::path(path).parent_path().string();
    piece.job = parse_job(meta["job"].dump(), path, folder.empty() ? "." : folder);
    if (sums->full_width != piece.job.width || sums->full_height != piece.job.height)
        fail_file(path, "the piece's image size disagrees with its job");
    try {
        validate_piece(piece.job, piece.range);
    } catch (const Error& e) {
        fail_file(path, e.what());
    }
    piece.exposure = meta.value("exposure", 1.f);
    piece.seconds = meta.value("seconds", 0.0);
    piece.film = piece_film(path, *sums, piece.range, format);
    return piece;
}

namespace {

// What makes two pieces parts of the same render: the job without its
// outputs, paths made absolute.
json job_identity(const RenderJob& job) {
    json j = json::parse(job_json(job, "/"));
    j.erase("outputs");
    return j;
}

bool overlap(const PieceRange& a, const PieceRange& b) {
    return a.samples.first < b.samples.last && b.samples.first < a.samples.last && a.pixels.x0 < b.pixels.x1 &&
           b.pixels.x0 < a.pixels.x1 && a.pixels.y0 < b.pixels.y1 && b.pixels.y0 < a.pixels.y1;
}

// Refuses piece `k` when its job is not the first piece's, or its range
// overlaps an earlier piece's. Checked as each piece is read, so that only
// the merged film and one piece are ever in memory (a 4K film is 1 GB).
void check_same_render(const std::vector<RenderPiece>& seen, const RenderPiece& piece, const json& first_job) {
    if (!seen.empty()) {
        const json patch = json::diff(first_job, job_identity(piece.job));
        if (!patch.empty())
            throw Error(seen[0].file + " and " + piece.file + " are pieces of different renders (their jobs' " +
                        patch[0].value("path", std::string("?")) + " differ)");
    }
    for (const RenderPiece& other : seen)
        if (overlap(other.range, piece.range))
            throw Error(other.file + " (" + range_text(other.range) + ") and " + piece.file + " (" +
                        range_text(piece.range) + ") overlap: merge each sample once");
}

// After the merge every pixel must hold samples 0:spp; names the first gap.
void check_complete(const std::vector<RenderPiece>& pieces, const Film& film, int spp) {
    std::size_t incomplete = 0;
    int gx = -1, gy = -1;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            if (film.samples(x, y) != spp && incomplete++ == 0) gx = x, gy = y;
    if (incomplete == 0) return;
    std::vector<SampleRange> held;
    for (const RenderPiece& p : pieces)
        if (gx >= p.range.pixels.x0 && gx < p.range.pixels.x1 && gy >= p.range.pixels.y0 && gy < p.range.pixels.y1)
            held.push_back(p.range.samples);
    std::sort(held.begin(), held.end(), [](const SampleRange& a, const SampleRange& b) { return a.first < b.first; });
    int from = 0;
    for (const SampleRange& r : held) {
        if (r.first > from) break;
        from = r.last;
    }
    int to = spp;
    for (const SampleRange& r : held)
        if (r.first >= from) to = std::min(to, r.first);
    throw Error("samples " + std::to_string(from) + ":" + std::to_string(to) + " of pixel (" + std::to_string(gx) +
                ", " + std::to_string(gy) + ") are in no piece (" + std::to_string(incomplete) + " of " +
                std::to_string(std::size_t(film.width()) * film.height()) +
                " pixels incomplete): render the missing piece and merge again");
}

}  // namespace

MergeResult merge_render_pieces(const std::vector<std::string>& files, const std::string& out_arg,
                                const std::string& png_arg) {
    if (files.empty()) throw Error("merge: give the pieces to merge");
    MergeResult result;
    // The pieces seen so far, without their films (only their ranges and jobs).
    std::vector<RenderPiece> seen;
    json first_job;
    for (const std::string& f : files) {
        const Stopwatch read_clock;
        RenderPiece piece = read_render_piece(f);
        result.read_seconds += read_clock.seconds();
        const Stopwatch merge_clock;
        if (seen.empty()) {
            first_job = job_identity(piece.job);
            result.job = piece.job;
            result.exposure = piece.exposure;
            result.film = Film(piece.job.width, piece.job.height);
        }
        check_same_render(seen, piece, first_job);
        result.film.merge(piece.film);
        result.piece_seconds += piece.seconds;
        piece.film = Film();
        seen.push_back(std::move(piece));
        result.merge_seconds += merge_clock.seconds();
    }
    result.pieces = int(seen.size());
    check_complete(seen, result.film, result.job.settings.spp);

    const std::string out = out_arg.empty() ? result.job.out : out_arg;
    std::string png = png_arg == "auto" ? sibling_path(out, ".png") : png_arg;
    if (png == out) png.clear();
    for (const std::string& path : {out, png})
        if (!path.empty()) require_output_folder(path);
    write_film(result.film, out, png, result.job.transparent, result.exposure);
    result.written.push_back(out);
    if (!png.empty()) result.written.push_back(png);
    return result;
}

}  // namespace jade
