#pragma once
// A batch of fits: a manifest lists photos, masks, meshes, output folders
// and flags; `jaderender batch MANIFEST --index I` runs entry I, so that a
// cluster's array job (one task per index) or a render farm's tasks run the
// whole manifest; `jaderender summary MANIFEST` gathers every entry's
// report.json into one table and their compare.png into one contact sheet.
//
// The manifest is JSON or CSV (by its extension); relative paths are
// relative to the manifest's folder:
//   {"flags": ["--resolution", "128"],            common to every entry
//    "entries": [{"photo": "a.jpg", "mask": "", "mesh": "vase.glb",
//                 "out": "out/a-vase", "flags": ["--fit", "bisect"]}, ...]}
//   photo,mask,mesh,out,flags                      a header, then one row
//   a.jpg,,vase.glb,out/a-vase,--fit bisect        per entry (flags split
//                                                  at spaces; no quoting)
// An entry without "out" writes to <photo stem>-<mesh stem>/ beside the
// manifest.

#include <string>
#include <vector>

namespace jade {

struct BatchEntry {
    std::string photo, mask, mesh, out;
    std::vector<std::string> flags;
};

struct BatchManifest {
    std::string file;
    std::vector<std::string> flags;  // before every entry's own
    std::vector<BatchEntry> entries;
};

// Reads and checks a manifest (throws jade::Error naming the file, and the
// entry, on any problem).
BatchManifest load_manifest(const std::string& path);

// The pipeline's command line for entry `index` (without the program's
// name): --photo, --mask, --mesh, --out, the common flags, the entry's flags.
std::vector<std::string> entry_arguments(const BatchManifest& manifest, int index);

// Creates the folder that holds entry `index`'s output folder (the fit
// creates the output folder itself), so a manifest may name out/<entry>
// before out/ exists. Throws jade::Error naming the folder when it cannot.
void create_entry_parent(const BatchManifest& manifest, int index);

// One row per entry from its report.json: status, fit, exposure, the
// appearance against the photo, the final render's error and the times.
// Entries that have no report (not run yet, or failed) are rows with status
// "missing" or "unreadable". Written whole or not at all.
struct BatchSummary {
    int done = 0, missing = 0;
};
BatchSummary write_batch_summary(const BatchManifest& manifest, const std::string& csv_path);

// Every entry's compare.png side by side in a grid, each scaled to
// `tile_width` pixels wide; a missing one is a grey tile. In manifest order,
// row by row (the summary's order).
void write_contact_sheet(const BatchManifest& manifest, const std::string& png_path, int tile_width = 480);

}  // namespace jade
