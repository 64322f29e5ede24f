#pragma once
// A render split into pieces that run anywhere (a cluster's array job, a
// render farm's tasks) and merge exactly. A piece is a range of sample
// indices of a rectangle of pixels; since each camera sample's random
// numbers are keyed by (seed, pixel, sample index) and the film's sums are
// exact integers (render/film.h), the merge of pieces that cover the render
// once is bit-identical to one render of all its samples.
//
// A piece's file is a two-part OpenEXR (io/exr_parts.h), named by its range
// beside the job's output (render.exr -> render.part-s0-64.exr):
//   "preview": the piece's mean as linear RGBA float, what any viewer shows;
//   "sums":    per pixel Σx and Σx² per channel as 128-bit integers in four
//              32-bit words each (sum.R.0 the lowest), the sample count and
//              the count of samples that met the object;
// and the attribute "jade:piece", JSON: the format version, the range, the
// image size, the job (paths relative to the piece's folder) and the PNG's
// exposure. docs/cluster.md describes it for other tools.

#include "jade/app/job.h"
#include "jade/render/film.h"
#include "jade/render/renderer.h"

#include <string>
#include <vector>

namespace jade {

struct PieceRange {
    SampleRange samples;
    PixelBounds pixels;
};

// "A:B" (samples A to B-1) and "x0:x1,y0:y1" (pixel columns x0 to x1-1 and
// rows y0 to y1-1). Throw jade::Error naming the flag.
SampleRange parse_sample_range(const std::string& text);
PixelBounds parse_pixel_bounds(const std::string& text);

// "I/N": piece I (from 0) of the render's samples cut into N nearly equal
// ranges (samples floor(I·spp/N) to floor((I+1)·spp/N) - 1 of every pixel),
// so that a scheduler's task needs only its index and the task count.
PieceRange parse_piece_of(const std::string& text, const RenderJob& job);

// Checks a piece against its job: inside samples 0:spp and the image, not
// empty, and the job's stops fixed (no --time, no --target-error).
void validate_piece(const RenderJob& job, const PieceRange& range);

// The piece's file, named by its range beside `out`: render.exr ->
// render.part-s0-64.exr, and for a tile render.part-s0-64-x0-256-y128-256.exr.
// A re-run of the same piece writes the same file.
std::string piece_path(const std::string& out, const PieceRange& range, int width, int height);

struct RenderPiece {
    std::string file;
    RenderJob job;        // paths resolved
    PieceRange range;
    Film film;            // the whole image's size; pixels outside the range hold no sample
    float exposure = 1.f; // the PNG's, as the render resolved it
    double seconds = 0.0; // rendering time of the piece
};

// Writes a piece, whole or not at all.
void write_render_piece(const std::string& path, const RenderJob& job, const PieceRange& range,
                        const Film& film, float exposure, double seconds);

// Reads a piece; a file that is not one, or whose sums disagree with its
// range, is refused with one line naming it.
RenderPiece read_render_piece(const std::string& path);

// The files of the N pieces `render --piece I/N` writes for `job` (its
// output as `out`, or the job's own when `out` is empty), in order.
std::vector<std::string> split_piece_paths(const RenderJob& job, int count, const std::string& out = "");

struct MergeResult {
    Film film;
    RenderJob job;
    float exposure = 1.f;
    int pieces = 0;
    double piece_seconds = 0.0;    // the pieces' rendering time, summed
    double read_seconds = 0.0, merge_seconds = 0.0;
    std::vector<std::string> written;
};

// Merges pieces of one job that cover samples 0:spp of every pixel exactly
// once, and writes the image as the whole render would: `out` (or the job's
// output when empty) and its PNG. Refuses pieces of different jobs,
// overlapping ranges and missing ones, each with one line naming the files or
// the range. The pieces are only read: merging again gives the same bits.
// They are read one at a time, so memory holds the merged film and one
// piece whatever their number (a 4K film is about 1 GB).
MergeResult merge_render_pieces(const std::vector<std::string>& pieces, const std::string& out,
                                const std::string& png = "auto");

}  // namespace jade
