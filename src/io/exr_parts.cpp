#include "jade/io/exr_parts.h"

#include "jade/core/error.h"
#include "jade/core/image.h"
#include "jade/core/quiet_stderr.h"
#include "jade/io/atomic_file.h"

#include <OpenImageIO/imageio.h>

namespace jade {

namespace OIIO = OIIO_NAMESPACE;

std::string ExrPart::attribute(const std::string& key) const {
    for (const auto& [k, v] : attributes)
        if (k == key) return v;
    return {};
}

int ExrPart::channel(const std::string& name) const {
    for (std::size_t i = 0; i < channels.size(); ++i)
        if (channels[i] == name) return int(i);
    return -1;
}

namespace {

OIIO::ImageSpec part_spec(const ExrPart& p) {
    const OIIO::TypeDesc type = p.integer ? OIIO::TypeDesc::UINT : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(p.width, p.height, int(p.channels.size()), type);
    spec.x = p.x0;
    spec.y = p.y0;
    spec.full_x = spec.full_y = 0;
    spec.full_width = p.full_width;
    spec.full_height = p.full_height;
    spec.channelnames = p.channels;
    spec.alpha_channel = -1;
    spec.attribute("name", p.name);
    spec.attribute("compression", "zip");
    for (const auto& [k, v] : p.attributes) spec.attribute(k, v);
    return spec;
}

void check_part(const std::string& path, const ExrPart& p) {
    const std::size_t n = std::size_t(p.width) * p.height * p.channels.size();
    if ((p.integer ? p.uints.size() : p.floats.size()) != n || p.x0 < 0 || p.y0 < 0 ||
        p.x0 + p.width > p.full_width || p.y0 + p.height > p.full_height)
        throw Error("internal: EXR part '" + p.name + "' of " + path + " does not match its window");
}

}  // namespace

void write_exr_parts(const std::string& path, const std::vector<ExrPart>& parts) {
    if (parts.empty()) throw Error("internal: no EXR parts to write to " + path);
    std::vector<OIIO::ImageSpec> specs;
    for (const ExrPart& p : parts) {
        check_part(path, p);
        specs.push_back(part_spec(p));
    }
    AtomicFile file(path);
    auto out = OIIO::ImageOutput::create("exr");
    if (!out || !out->supports("multiimage")) fail_file(path, "no multi-part EXR writer");
    bool ok = out->open(file.temp_path(), int(specs.size()), specs.data());
    for (std::size_t i = 0; ok && i < parts.size(); ++i) {
        if (i > 0) ok = out->open(file.temp_path(), specs[i], OIIO::ImageOutput::AppendSubimage);
        const void* data = parts[i].integer ? static_cast<const void*>(parts[i].uints.data())
                                            : static_cast<const void*>(parts[i].floats.data());
        ok = ok && out->write_image(parts[i].integer ? OIIO::TypeDesc::UINT : OIIO::TypeDesc::FLOAT, data);
    }
    if (!ok || !out->close()) fail_file(path, "cannot write: " + out->geterror());
    file.commit();
}

namespace {

std::vector<ExrPart> read_parts(const std::string& path, int max_parts, int max_channels);

ExrPart read_part(const std::string& path, OIIO::ImageInput& in, int max_channels) {
    const OIIO::ImageSpec& spec = in.spec();
    ExrPart p;
    p.name = spec.get_string_attribute("name");
    p.full_width = spec.full_width;
    p.full_height = spec.full_height;
    p.x0 = spec.x - spec.full_x;
    p.y0 = spec.y - spec.full_y;
    p.width = spec.width;
    p.height = spec.height;
    if (spec.nchannels < 1 || spec.nchannels > max_channels || spec.depth != 1)
        fail_file(path, "part '" + p.name + "' has " + std::to_string(spec.nchannels) + " channels, not ours");
    if (p.width < 1 || p.height < 1 || p.x0 < 0 || p.y0 < 0 || p.x0 + std::int64_t(p.width) > p.full_width ||
        p.y0 + std::int64_t(p.height) > p.full_height ||
        std::int64_t(p.full_width) * p.full_height > kMaxImagePixels)
        fail_file(path, "part '" + p.name + "' has an impossible size or window");
    p.channels = spec.channelnames;
    p.integer = spec.format == OIIO::TypeDesc::UINT;
    for (const OIIO::ParamValue& a : spec.extra_attribs)
        if (a.type() == OIIO::TypeDesc::STRING) p.attributes.emplace_back(a.name().string(), a.get_string());
    const std::size_t n = std::size_t(p.width) * p.height * p.channels.size();
    bool read = false;
    if (p.integer) {
        p.uints.resize(n);
        read = in.read_image(in.current_subimage(), 0, 0, spec.nchannels, OIIO::TypeDesc::UINT, p.uints.data());
    } else {
        p.floats.resize(n);
        read = in.read_image(in.current_subimage(), 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, p.floats.data());
    }
    const std::string message = in.geterror();
    if (!read || !message.empty())
        fail_file(path, "cannot decode part '" + p.name + "'" + (message.empty() ? "" : ": " + message));
    return p;
}

}  // namespace

std::vector<ExrPart> read_exr_parts(const std::string& path, int max_parts, int max_channels) {
    try {
        return read_parts(path, max_parts, max_channels);
    } catch (const std::bad_alloc&) {
        fail_file(path, "damaged: its header asks for more memory than an image of its size needs");
    }
}

namespace {
std::vector<ExrPart> read_parts(const std::string& path, int max_parts, int max_channels) {
    const QuietStderr quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        const std::string why = OIIO::geterror();
        fail_file(path, why.empty() ? "cannot open as an image" : "cannot read: " + why);
    }
    if (std::string(in->format_name()) != "openexr") fail_file(path, "is not an OpenEXR file");
    std::vector<ExrPart> parts;
    for (int i = 0; in->seek_subimage(i, 0); ++i) {
        if (i >= max_parts) fail_file(path, "holds more than " + std::to_string(max_parts) + " parts");
        parts.push_back(read_part(path, *in, max_channels));
    }
    in->geterror();  // seeking past the last part leaves a message that is no error
    return parts;
}
}  // namespace

}  // namespace jade
