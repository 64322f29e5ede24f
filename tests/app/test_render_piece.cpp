// A render split into pieces written to disk — sample ranges, tiles, uneven
// and in any order — and merged is bit-identical to one render of all its
// samples; a merge that would not be is refused with one line.

#include "jade/app/render_job.h"
#include "jade/app/render_piece.h"
#include "jade/core/error.h"
#include "jade/io/exr_parts.h"
#include "jade/io/image_io.h"

#include "support/test_util.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <algorithm>
#include <fstream>
#include <iterator>

using namespace jade;
using jade_test::TempDir;

namespace {

// A small render with long, wide-ranging paths: a deep homogeneous medium
// behind the dielectric blob, the disc light and a coloured environment.
RenderJob small_job(const TempDir& dir) {
    RenderJob job;
    job.mesh = JADE_DATA_DIR "/reference/blob.obj";
    job.sigma_s = Spectrum(3.8f, 7.2f, 9.6f);
    job.sigma_a = Spectrum(0.2f, 0.8f, 2.4f);
    job.environment = "0.2,0.3,0.4";
    job.width = 40;
    job.height = 32;
    job.settings.spp = 29;
    job.settings.seed = 11;
    job.out = dir.file("render.exr");
    job.convergence = "";
    return job;
}

bool same_film(const Film& a, const Film& b) {
    return a.width() == b.width() && a.height() == b.height() && a.sums() == b.sums() &&
           a.sums_of_squares() == b.sums_of_squares() && a.counts() == b.counts() &&
           a.object_hits() == b.object_hits() && a.stratum_sums() == b.stratum_sums() &&
           a.stratum_counts() == b.stratum_counts();
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

bool same_pixels(const std::string& a, const std::string& b) {
    const ImageF32 x = read_image_f32(a), y = read_image_f32(b);
    return x.width == y.width && x.height == y.height && x.channels == y.channels &&
           std::memcmp(x.pixels.data(), y.pixels.data(), x.pixels.size() * sizeof(float)) == 0;
}

std::vector<std::string> render_pieces(const RenderJob& job, const std::vector<PieceRange>& ranges) {
    std::vector<std::string> files;
    for (const PieceRange& r : ranges) {
        const RenderJobResult res = run_render_job(job, nullptr, nullptr, &r);
        REQUIRE(res.written.size() == 1);
        files.push_back(res.written[0]);
    }
    return files;
}

std::vector<PieceRange> sample_cuts(const RenderJob& job, const std::vector<int>& cuts) {
    std::vector<PieceRange> ranges;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
        ranges.push_back({{cuts[k], cuts[k + 1]}, {0, 0, job.width, job.height}});
    return ranges;
}

}  // namespace

TEST_CASE("pieces written to disk and merged give the whole render's bits", "[piece]") {
    TempDir dir;
    const RenderJob job = small_job(dir);
    const RenderJobResult whole = run_render_job(job);
    REQUIRE(whole.render.film.spp() == 29);

    auto check_merge = [&](const std::vector<std::string>& files, const std::string& name) {
        const MergeResult m = merge_render_pieces(files, dir.file(name + ".exr"));
        CHECK(m.pieces == int(files.size()));
        CHECK(same_film(m.film, whole.render.film));
        CHECK(same_pixels(dir.file(name + ".exr"), job.out));
        CHECK(same_pixels(dir.file(name + ".png"), dir.file("render.png")));
    };
    SECTION("2, 4 and 7 sample ranges, uneven, merged in any order") {
        check_merge(render_pieces(job, sample_cuts(job, {0, 14, 29})), "two");
        std::vector<std::string> four = render_pieces(job, sample_cuts(job, {0, 1, 2, 20, 29}));
        std::reverse(four.begin(), four.end());
        check_merge(four, "four");
        check_merge(render_pieces(job, sample_cuts(job, {0, 3, 4, 9, 10, 17, 28, 29})), "seven");
    }
    SECTION("tiles, each in two sample ranges") {
        std::vector<PieceRange> ranges;
        for (const PixelBounds& b : {PixelBounds{0, 0, 17, 32}, PixelBounds{17, 0, 40, 5}, PixelBounds{17, 5, 40, 32}})
            for (const SampleRange& s : {SampleRange{0, 12}, SampleRange{12, 29}}) ranges.push_back({s, b});
        const std::vector<std::string> files = render_pieces(job, ranges);
        CHECK(files[0] == dir.file("render.part-s0-12-x0-17-y0-32.exr"));
        check_merge(files, "tiles");
    }
    SECTION("merging again gives the same bits and leaves the pieces as they were") {
        const std::vector<std::string> files = render_pieces(job, sample_cuts(job, {0, 10, 29}));
        const std::string before = slurp(files[0]);
        const MergeResult a = merge_render_pieces(files, dir.file("a.exr"));
        const MergeResult b = merge_render_pieces(files, dir.file("b.exr"));
        CHECK(same_film(a.film, b.film));
        CHECK(same_pixels(dir.file("a.exr"), dir.file("b.exr")));
        CHECK(slurp(files[0]) == before);
    }
}

TEST_CASE("a piece re-rendered after a failure is the same file's content", "[piece]") {
    TempDir dir;
    const RenderJob job = small_job(dir);
    const PieceRange r{{5, 9}, {0, 0, job.width, job.height}};
    const std::string path = render_pieces(job, {r})[0];
    const Film first = read_render_piece(path).film;
    std::filesystem::remove(path);
    render_pieces(job, {r});
    CHECK(same_film(read_render_piece(path).film, first));
}

TEST_CASE("merge refuses what would not be the render: one line naming the files", "[piece]") {
    TempDir dir;
    const RenderJob job = small_job(dir);
    const std::vector<std::string> files = render_pieces(job, sample_cuts(job, {0, 10, 20, 29}));
    auto refused = [](const std::vector<std::string>& f, const std::string& words) {
        try {
            merge_render_pieces(f, "");
            FAIL("merged");
        } catch (const Error& e) {
            CHECK_THAT(e.what(), Catch::Contains(words));
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
        }
    };
    refused({files[0], files[2]}, "samples 10:20 of pixel (0, 0) are in no piece");
    refused({files[0], files[1]}, "samples 20:29 of pixel (0, 0) are in no piece");
    refused({files[0], files[1], files[2], files[1]}, "overlap");
    const std::vector<std::string> tile =
        render_pieces(job, {{{10, 20}, {0, 0, 8, 8}}});
    refused({files[0], files[1], files[2], tile[0]}, "overlap");

    RenderJob other = job;
    other.settings.seed = 12;
    other.out = dir.file("other.exr");
    const std::vector<std::string> foreign = render_pieces(other, sample_cuts(other, {20, 29}));
    refused({files[0], files[1], foreign[0]}, "pieces of different renders (their jobs' /settings/seed differ)");

    // A piece whose sums were altered no longer agrees with its range.
    std::vector<ExrPart> parts = read_exr_parts(files[2], 2, 128);
    REQUIRE(parts.size() == 2);
    parts[1].uints[std::size_t(parts[1].channel("count"))] += 1;
    write_exr_parts(dir.file("altered.exr"), parts);
    refused({files[0], files[1], dir.file("altered.exr")}, "altered.exr: a pixel's sample count disagrees");
    refused({files[0], files[1], JADE_DATA_DIR "/reference/sceneA_ref.exr"}, "sceneA_ref.exr: is not a piece");
    CHECK_FALSE(std::filesystem::exists(job.out));
    CHECK_FALSE(std::filesystem::exists(dir.file("render.png")));
}

TEST_CASE("range flags: parsed strictly, checked against the job", "[piece]") {
    CHECK(parse_sample_range("3:17").first == 3);
    CHECK(parse_sample_range("3:17").last == 17);
    for (const char* bad : {"", "5", "5:5", "7:3", "-1:4", "1:2:3", "a:b", "1.5:3", "0:99999999999"})
        CHECK_THROWS_AS(parse_sample_range(bad), Error);
    const PixelBounds b = parse_pixel_bounds("2:10,4:6");
    CHECK((b.x0 == 2 && b.x1 == 10 && b.y0 == 4 && b.y1 == 6));
    for (const char* bad : {"", "2:10", "2:10,6:4", "0:0,0:1", "x"}) CHECK_THROWS_AS(parse_pixel_bounds(bad), Error);

    TempDir dir;
    RenderJob job = small_job(dir);
    // I/N: N nearly equal ranges that cover 0:spp (29) once.
    int next = 0;
    for (int i = 0; i < 4; ++i) {
        const PieceRange r = parse_piece_of(std::to_string(i) + "/4", job);
        CHECK(r.samples.first == next);
        CHECK(r.samples.last - r.samples.first >= 7);
        CHECK(r.samples.last - r.samples.first <= 8);
        next = r.samples.last;
    }
    CHECK(next == 29);
    CHECK(parse_piece_of("0/1", job).samples.last == 29);
    for (const char* bad : {"4/4", "1", "/4", "1/0", "-1/4", "0/30"}) CHECK_THROWS_AS(parse_piece_of(bad, job), Error);
    CHECK_THROWS_WITH(validate_piece(job, {{0, 30}, {0, 0, 40, 32}}), Catch::Contains("0:29 (--spp)"));
    CHECK_THROWS_WITH(validate_piece(job, {{0, 4}, {0, 0, 41, 32}}), Catch::Contains("40 x 32"));
    job.settings.time_limit = 5;
    CHECK_THROWS_WITH(validate_piece(job, {{0, 4}, {0, 0, 40, 32}}), Catch::Contains("--time"));
}

TEST_CASE("a piece of format 1, written before the film kept its strata, reads as one stratum and replicate", "[piece]") {
    TempDir dir;
    const RenderJob job = small_job(dir);
    const std::vector<std::string> files = render_pieces(job, sample_cuts(job, {0, 29}));
    const RenderPiece now = read_render_piece(files[0]);
    // The same piece as format 1 wrote it: no stratum or replicate channels, "format": 1.
    std::vector<ExrPart> parts = read_exr_parts(files[0], 2, 128);
    REQUIRE(parts.size() == 2);
    ExrPart& sums = parts[1];
    std::vector<int> kept;
    std::vector<std::string> names;
    for (std::size_t k = 0; k < sums.channels.size(); ++k)
        if (sums.channels[k].rfind("stratum", 0) != 0 && sums.channels[k].rfind("replicate", 0) != 0) {
            kept.push_back(int(k));
            names.push_back(sums.channels[k]);
        }
    REQUIRE(kept.size() < sums.channels.size());
    std::vector<std::uint32_t> old;
    for (std::size_t p = 0; p < sums.uints.size() / sums.channels.size(); ++p)
        for (int k : kept) old.push_back(sums.uints[p * sums.channels.size() + std::size_t(k)]);
    sums.channels = names;
    sums.uints = old;
    for (auto& [key, value] : sums.attributes)
        if (key == "jade:piece") {
            const std::size_t at = value.find("\"format\":3");
            REQUIRE(at != std::string::npos);
            value.replace(at, 10, "\"format\":1");
        }
    write_exr_parts(dir.file("old.exr"), parts);
    const RenderPiece then = read_render_piece(dir.file("old.exr"));
    CHECK(then.film.sums() == now.film.sums());
    CHECK(then.film.sums_of_squares() == now.film.sums_of_squares());
    CHECK(then.film.counts() == now.film.counts());
    for (std::uint32_t n : then.film.stratum_counts()) CHECK(n == 0);
    for (std::uint32_t n : then.film.replicate_counts()) CHECK(n == 0);
    // One stratum: the pixel is Σx / n, with the sample variance.
    const double n = then.film.counts()[0];
    const double sum = double(then.film.sums()[0]) / 18446744073709551616.0;
    CHECK(then.film.mean(0, 0).x == Approx(sum / n));
    // And every pixel the sample variance over n (no replicates to take it from).
    for (int y = 0; y < then.film.height(); ++y)
        for (int x = 0; x < then.film.width(); ++x) {
            const std::size_t i = std::size_t(y) * then.film.width() + x;
            const double s = double(then.film.sums()[3 * i]) / 18446744073709551616.0;
            const double sq = double(then.film.sums_of_squares()[3 * i]) / 18446744073709551616.0;
            const double expected = std::max(0.0, (sq - s * s / n) / (n - 1)) / n;
            CHECK(then.film.variance_of_mean(x, y).x == Approx(expected).margin(1e-12));
        }
}
