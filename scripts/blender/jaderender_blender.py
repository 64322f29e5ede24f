"""Rebuild a jaderender result in Blender and render it with Cycles.

    blender -b --python jaderender_blender.py -- [REPORT] [options]

REPORT is a jaderender report.json (the pipeline writes one beside its outputs,
and a copy of this script as blender.py beside it) or a render job document
(`jaderender render --job`). Without it, the report.json beside this script is
used, so the copy in an output folder runs as it is, also from Blender's text
editor (Run Script). Options:

    --render FILE.png    render and write the display image (sRGB, the fit's exposure)
    --exr FILE.exr       render and write linear radiance (no exposure), like render.exr
    --samples N          samples per pixel (default: the job's)
    --seed N             Cycles' seed (default: the job's)
    --width W --height H image size (default: the job's)
    --save FILE.blend    save the scene
    --step-rate R        Cycles' volume step rate for a grid (default 0.25)

The scene follows docs/blender.md, which gives the reasons:
- jaderender's world is Y-up, Blender's Z-up: (x, y, z) -> (x, -z, y). The mesh
  importers turn the mesh; a Y-up .vdb is turned by +90 degrees about x.
- The medium is the .vdb's sigma_s and sigma_a grids in world units: one
  Volume Scatter whose colour is sigma_s (density 1), and three Volume
  Absorption closures, one per channel (Cycles absorbs (1 - colour) x density).
  A homogeneous medium uses the same closures with constant values.
- The boundary: 'none' is Transparent, 'fresnel' a sharp Glass, 'split' (the
  paper's reflect-with-weight-s) a mix of sharp Glossy and sharp Refraction
  that turns to Glossy alone where refraction is impossible.
- The directional light is a Sun of angle 2 x radius and strength
  E x 2 / (1 + cos radius): Cycles' sun of strength S delivers
  S (1 + cos radius) / 2 to a surface facing it, jaderender's disc delivers E.
  A delta light (radius 0, jaderender's default) behind a refracting boundary
  becomes a sun of radius DELTA_SUN_DEGREES: Cycles reaches the inside of
  glass only by paths that leave it and meet the sun, which never meet a
  delta sun (jaderender solves for the refraction instead).
- Film: box filter one pixel wide, Standard view transform, exposure
  log2(jaderender's exposure) stops, no clamping, no denoising, all bounces.

Works with Debian 12's Blender 3.4 and with Blender 4.x.
"""

import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector


class JobError(Exception):
    """A problem with the job or its files: one line, exit 2."""


# The radius, in degrees, of the sun that stands in for a delta light behind
# a refracting boundary (docs/blender.md, "What the script builds").
DELTA_SUN_DEGREES = 10.0


# ---------------------------------------------------------------------------
# Arguments and the job


def parse_args(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    opts = {"report": None, "render": None, "exr": None, "samples": None, "seed": None, "width": None,
            "height": None, "save": None, "step_rate": 0.25}
    names = {"--render": "render", "--exr": "exr", "--samples": "samples", "--seed": "seed",
             "--width": "width", "--height": "height", "--save": "save",
             "--step-rate": "step_rate"}
    numbers = {"samples": int, "seed": int, "width": int, "height": int, "step_rate": float}
    i = 0
    while i < len(args):
        a = args[i]
        if a in names:
            if i + 1 >= len(args):
                raise JobError(a + " needs a value")
            key = names[a]
            try:
                opts[key] = numbers[key](args[i + 1]) if key in numbers else args[i + 1]
            except ValueError:
                raise JobError(a + " needs a number, not '" + args[i + 1] + "'")
            i += 2
        elif a.startswith("--"):
            raise JobError("unknown option " + a)
        else:
            opts["report"] = a
            i += 1
    if opts["report"] is None:
        opts["report"] = os.path.join(script_folder(), "report.json")
    return opts


def script_folder():
    """The folder of this script, whether run by --python or from the text editor."""
    try:
        return os.path.dirname(os.path.abspath(__file__))
    except NameError:
        pass
    for text in bpy.data.texts:
        if text.filepath:
            return os.path.dirname(bpy.path.abspath(text.filepath))
    return os.getcwd()


def load_job(path):
    """The render job of a report.json or a job document, and its folder."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except OSError as e:
        raise JobError(path + ": " + e.strerror)
    except ValueError as e:
        raise JobError(path + ": not valid JSON: " + str(e))
    job = doc.get("job", doc) if isinstance(doc, dict) else None
    if not isinstance(job, dict) or "scene" not in job:
        raise JobError(path + ": holds no render job ('scene' is missing)")
    volume_info = doc.get("volume", {}) if "job" in doc else {}
    return job, volume_info, os.path.dirname(os.path.abspath(path))


def resolve(base, p):
    return p if not p or os.path.isabs(p) else os.path.normpath(os.path.join(base, p))


def y_up_to_z_up(v):
    """jaderender's world (Y-up, like glTF) in Blender's (Z-up)."""
    return Vector((v[0], -v[2], v[1]))


def parse_colour(text):
    """A constant environment 'v' or 'r,g,b', or None for a file name."""
    try:
        parts = [float(x) for x in str(text).split(",")]
    except ValueError:
        return None
    if len(parts) == 1:
        return parts * 3
    if len(parts) == 3:
        return parts
    return None


# ---------------------------------------------------------------------------
# Objects


def import_mesh(path, flat):
    """The mesh's objects, turned Z-up by Blender's importers (as glTF asks)."""
    if not os.path.isfile(path):
        raise JobError(path + ": no such mesh")
    before = set(bpy.data.objects)
    ext = os.path.splitext(path)[1].lower()
    if ext in (".glb", ".gltf"):
        import warnings
        import numpy
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            missing = not hasattr(numpy, "bool")
        if missing:
            # Debian 12's glTF importer still names numpy.bool, gone from its numpy.
            numpy.bool = bool
        bpy.ops.import_scene.gltf(filepath=path)
    elif ext == ".obj":
        if hasattr(bpy.ops.wm, "obj_import"):
            bpy.ops.wm.obj_import(filepath=path)
        else:
            bpy.ops.import_scene.obj(filepath=path)
    else:
        raise JobError(path + ": not a mesh Blender imports here (.glb, .gltf, .obj)")
    new = [o for o in bpy.data.objects if o not in before]
    meshes = [o for o in new if o.type == "MESH"]
    for o in new:
        if o.type in ("CAMERA", "LIGHT"):  # the job's camera and light are used instead
            bpy.data.objects.remove(o)
    if not meshes:
        raise JobError(path + ": holds no mesh")
    for o in meshes:
        for poly in o.data.polygons:
            poly.use_smooth = not flat
    return meshes


def import_volume(path, z_up):
    if not os.path.isfile(path):
        raise JobError(path + ": no such volume")
    data = bpy.data.volumes.new("jaderender volume")
    data.filepath = path
    data.grids.load()
    names = {g.name for g in data.grids}
    if not {"sigma_s", "sigma_a"} <= names:
        raise JobError(path + ": has no sigma_s and sigma_a grids (grids: " + ", ".join(sorted(names)) + ")")
    obj = bpy.data.objects.new("jaderender volume", data)
    bpy.context.scene.collection.objects.link(obj)
    if not z_up:
        obj.rotation_euler = (math.pi / 2, 0.0, 0.0)  # (x, y, z) -> (x, -z, y)
    return obj


# ---------------------------------------------------------------------------
# Materials


class Nodes:
    """A material's node tree, emptied, with small helpers."""

    def __init__(self, material):
        material.use_nodes = True
        self.tree = material.node_tree
        for n in list(self.tree.nodes):
            self.tree.nodes.remove(n)
        self.output = self.new("ShaderNodeOutputMaterial")

    def new(self, kind, **inputs):
        node = self.tree.nodes.new(kind)
        for name, value in inputs.items():
            node.inputs[name].default_value = value
        return node

    def link(self, out, inp):
        self.tree.links.new(out, inp)

    def math(self, op, a, b):
        node = self.new("ShaderNodeMath")
        node.operation = op
        for socket, v in zip(node.inputs, (a, b)):
            if isinstance(v, (int, float)):
                socket.default_value = v
            else:
                self.link(v, socket)
        return node.outputs[0]

    def mix(self, fac, a, b):
        """(1 - fac) a + fac b; fac a number or a socket."""
        node = self.new("ShaderNodeMixShader")
        if isinstance(fac, (int, float)):
            node.inputs["Fac"].default_value = fac
        else:
            self.link(fac, node.inputs["Fac"])
        self.link(a, node.inputs[1])
        self.link(b, node.inputs[2])
        return node.outputs[0]

    def add(self, a, b):
        node = self.new("ShaderNodeAddShader")
        self.link(a, node.inputs[0])
        self.link(b, node.inputs[1])
        return node.outputs[0]


def sharp(node):
    """A delta lobe: 'SHARP' in Blender 3.x, roughness 0 in 4.x (which dropped it)."""
    if "SHARP" in {i.identifier for i in node.bl_rna.properties["distribution"].enum_items}:
        node.distribution = "SHARP"
    else:
        node.distribution = "GGX"
    if "Roughness" in node.inputs:
        node.inputs["Roughness"].default_value = 0.0
    return node


def boundary_shader(n, scene_job):
    mode, ior = scene_job.get("boundary", "split"), float(scene_job.get("ior", 1.6))
    white = (1.0, 1.0, 1.0, 1.0)
    if mode == "none":
        return n.new("ShaderNodeBsdfTransparent", Color=white).outputs[0]
    if mode == "fresnel":
        return sharp(n.new("ShaderNodeBsdfGlass", Color=white, IOR=ior)).outputs[0]
    if mode != "split":
        raise JobError("scene.boundary '" + mode + "' is not one of split, fresnel, none")
    s = float(scene_job.get("specular", 0.5))
    glossy = sharp(n.new("ShaderNodeBsdfGlossy", Color=white)).outputs[0]
    refraction = sharp(n.new("ShaderNodeBsdfRefraction", Color=white, IOR=ior)).outputs[0]
    both = n.mix(1.0 - s, glossy, refraction)  # s x reflection + (1 - s) x refraction
    # Total internal reflection: from inside (back face) beyond the critical
    # angle all goes to the reflection, as jaderender's split does; Cycles'
    # Refraction alone would lose it.
    geometry = n.new("ShaderNodeNewGeometry")
    cos_i = n.new("ShaderNodeVectorMath")
    cos_i.operation = "DOT_PRODUCT"
    n.link(geometry.outputs["Normal"], cos_i.inputs[0])
    n.link(geometry.outputs["Incoming"], cos_i.inputs[1])
    dot = cos_i.outputs["Value"]
    cos_critical = math.sqrt(max(0.0, 1.0 - 1.0 / (ior * ior)))
    beyond = n.math("LESS_THAN", n.math("ABSOLUTE", dot, 0.0), cos_critical)
    tir = n.math("MULTIPLY", beyond, geometry.outputs["Backfacing"])
    return n.mix(tir, both, glossy)


def medium_shader(n, sigma_s, sigma_a, g, inside=None):
    """Scattering sigma_s and absorption sigma_a per world unit; each an RGB
    triple or an (attribute) socket giving one. `inside`, a socket of 1 or 0,
    multiplies both."""
    if inside is not None:
        scaled = []
        for sigma in (sigma_s, sigma_a):
            scale = n.new("ShaderNodeVectorMath")
            scale.operation = "SCALE"
            n.link(sigma, scale.inputs[0])
            n.link(inside, scale.inputs["Scale"])
            scaled.append(scale.outputs[0])
        sigma_s, sigma_a = scaled
    scatter = n.new("ShaderNodeVolumeScatter", Density=1.0, Anisotropy=g)
    if isinstance(sigma_s, list):
        scatter.inputs["Color"].default_value = (*sigma_s, 1.0)
    else:
        n.link(sigma_s, scatter.inputs["Color"])
    if isinstance(sigma_a, list):
        components = sigma_a
    else:
        split = n.new("ShaderNodeSeparateXYZ")
        n.link(sigma_a, split.inputs[0])
        components = [split.outputs[k] for k in range(3)]
    total = scatter.outputs[0]
    for c in range(3):
        keep = [1.0, 1.0, 1.0, 1.0]
        keep[c] = 0.0  # absorbs (1 - colour) x density: channel c only
        absorb = n.new("ShaderNodeVolumeAbsorption", Color=tuple(keep))
        if isinstance(components[c], float):
            absorb.inputs["Density"].default_value = components[c]
        else:
            n.link(components[c], absorb.inputs["Density"])
        total = n.add(total, absorb.outputs[0])
    return total


def grid_attribute(n, name, output="Vector"):
    node = n.new("ShaderNodeAttribute")
    node.attribute_name = name
    return node.outputs[output]


def build_materials(job, meshes, volume_obj, step_rate):
    scene_job, medium = job["scene"], job.get("medium", {})
    g = float(scene_job.get("g", 0.0))
    boundary = bpy.data.materials.new("jaderender boundary")
    n = Nodes(boundary)
    n.link(boundary_shader(n, scene_job), n.output.inputs["Surface"])
    if volume_obj is None:
        n.link(medium_shader(n, [float(x) for x in medium["sigma_s"]], [float(x) for x in medium["sigma_a"]], g),
               n.output.inputs["Volume"])
    for o in meshes:
        o.data.materials.clear()
        o.data.materials.append(boundary)
    if volume_obj is not None:
        stone = bpy.data.materials.new("jaderender medium")
        v = Nodes(stone)
        inside = None
        if "surface_distance" in {grid.name for grid in volume_obj.data.grids}:
            # The grids reach one voxel beyond the mesh so that interpolation
            # inside it reads stone: cut them at the surface.
            inside = v.math("LESS_THAN", grid_attribute(v, "surface_distance", "Fac"), 0.0)
        v.link(medium_shader(v, grid_attribute(v, "sigma_s"), grid_attribute(v, "sigma_a"), g, inside),
               v.output.inputs["Volume"])
        volume_obj.data.materials.append(stone)
        bpy.context.scene.cycles.volume_step_rate = step_rate


# ---------------------------------------------------------------------------
# Camera, light, world, film


def add_camera(camera_job, width, height):
    if "origin" not in camera_job or "target" not in camera_job:
        raise JobError("the job's camera has no origin and target (report.json always has them)")
    origin = y_up_to_z_up(camera_job["origin"])
    forward = (y_up_to_z_up(camera_job["target"]) - origin).normalized()
    up = y_up_to_z_up(camera_job.get("up", [0.0, 1.0, 0.0]))
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    rotation = Matrix((right, true_up, -forward)).transposed()  # columns: camera x, y, z
    data = bpy.data.cameras.new("jaderender camera")
    data.sensor_fit = "HORIZONTAL"  # jaderender's field of view is horizontal
    data.angle = math.radians(float(camera_job.get("fov_degrees", 40.0)))
    data.clip_start = 1e-4 * max(1e-6, (y_up_to_z_up(camera_job["target"]) - origin).length)
    obj = bpy.data.objects.new("jaderender camera", data)
    obj.matrix_world = Matrix.Translation(origin) @ rotation.to_4x4()
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100


def add_sun(lights, boundary):
    # A glTF light file is read by jaderender, which writes what it found
    # into the jobs it writes (report.json's job: lights.file_resolved).
    if lights.get("file") and not lights.get("file_resolved"):
        raise JobError("lights.file: this job's light is in a glTF file that only jaderender reads; use the "
                       "report.json of a jaderender run with it (it carries the file's light) or give lights.direction")
    irradiance = float(lights.get("irradiance", 3.0))
    if irradiance <= 0.0:
        return
    degrees = float(lights.get("radius_degrees", 0.0))
    stand_in = degrees <= 0.0 and boundary != "none"
    if stand_in:
        degrees = DELTA_SUN_DEGREES
        print("jaderender_blender: the job's light is a delta light, which Cycles cannot reach through the "
              "refracting boundary; it becomes a sun of %g degrees in radius (same irradiance) that glossy "
              "rays do not see, as a delta light has no highlight" % degrees)
    radius = math.radians(degrees)
    data = bpy.data.lights.new("jaderender sun", "SUN")
    data.angle = 2.0 * radius
    data.energy = irradiance * 2.0 / (1.0 + math.cos(radius))
    toward = y_up_to_z_up(lights.get("direction", [0.17, 0.42, 0.89])).normalized()
    obj = bpy.data.objects.new("jaderender sun", data)
    obj.rotation_euler = toward.to_track_quat("Z", "Y").to_euler()  # a sun shines along its -z
    if stand_in:
        obj.visible_glossy = False
    bpy.context.scene.collection.objects.link(obj)


def add_world(lights, base):
    world = bpy.data.worlds.new("jaderender world")
    world.use_nodes = True
    tree = world.node_tree
    for node in list(tree.nodes):
        tree.nodes.remove(node)
    output = tree.nodes.new("ShaderNodeOutputWorld")
    env = tree.nodes.new("ShaderNodeBackground")
    env.inputs["Strength"].default_value = float(lights.get("environment_scale", 1.0))
    text = lights.get("environment", "0.01")
    colour = parse_colour(text)
    if colour is not None:
        env.inputs["Color"].default_value = (*colour, 1.0)
    else:
        # jaderender's lat-long image centre looks along its -z (Blender's +y),
        # Blender's along +x: turn the lookup by -90 degrees about z.
        coords = tree.nodes.new("ShaderNodeTexCoord")
        turn = tree.nodes.new("ShaderNodeMapping")
        turn.vector_type = "POINT"
        turn.inputs["Rotation"].default_value = (0.0, 0.0, -math.pi / 2)
        image = tree.nodes.new("ShaderNodeTexEnvironment")
        image.image = load_image(resolve(base, text))
        image.interpolation = "Linear"
        tree.links.new(coords.outputs["Generated"], turn.inputs["Vector"])
        tree.links.new(turn.outputs["Vector"], image.inputs["Vector"])
        tree.links.new(image.outputs["Color"], env.inputs["Color"])
    shader = env.outputs[0]
    if lights.get("background"):
        # What camera rays that miss see: an image stretched over the film.
        coords = tree.nodes.new("ShaderNodeTexCoord")
        image = tree.nodes.new("ShaderNodeTexImage")
        image.image = load_image(resolve(base, lights["background"]))
        image.extension = "EXTEND"
        back = tree.nodes.new("ShaderNodeBackground")
        path = tree.nodes.new("ShaderNodeLightPath")
        mix = tree.nodes.new("ShaderNodeMixShader")
        tree.links.new(coords.outputs["Window"], image.inputs["Vector"])
        tree.links.new(image.outputs["Color"], back.inputs["Color"])
        tree.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
        tree.links.new(shader, mix.inputs[1])
        tree.links.new(back.outputs[0], mix.inputs[2])
        shader = mix.outputs[0]
    tree.links.new(shader, output.inputs["Surface"])
    bpy.context.scene.world = world


def load_image(path):
    if not os.path.isfile(path):
        raise JobError(path + ": no such image")
    image = bpy.data.images.load(path)
    image.colorspace_settings.name = "Linear" if "Linear" in colour_spaces(image) else "Linear Rec.709"
    return image


def colour_spaces(image):
    return {i.identifier for i in image.colorspace_settings.bl_rna.properties["name"].enum_items}


def set_film(job, samples, seed):
    scene = bpy.context.scene
    cycles = scene.cycles
    scene.render.engine = "CYCLES"
    cycles.device = "CPU"
    cycles.samples = samples
    cycles.seed = seed
    cycles.use_denoising = False
    if hasattr(cycles, "use_adaptive_sampling"):
        cycles.use_adaptive_sampling = False
    depth = min(1024, int(job.get("settings", {}).get("max_depth", 4096)))
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                    "volume_bounces", "transparent_max_bounces"):
        setattr(cycles, bounces, depth)
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.gamma = 1.0
    exposure = float(job.get("outputs", {}).get("exposure", 1.0))
    scene.view_settings.exposure = math.log2(exposure) if exposure > 0.0 else 0.0
    scene.render.film_transparent = bool(job.get("lights", {}).get("transparent", False))


def render(scene, png, exr):
    bpy.ops.render.render()
    result = bpy.data.images["Render Result"]
    settings = scene.render.image_settings
    alpha = "RGBA" if scene.render.film_transparent else "RGB"
    if png:
        settings.file_format, settings.color_mode, settings.color_depth = "PNG", alpha, "8"
        result.save_render(png, scene=scene)
        print("wrote " + png)
    if exr:
        settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
        result.save_render(exr, scene=scene)  # linear: the view transform is for display formats only
        print("wrote " + exr)


# ---------------------------------------------------------------------------


def build_scene(opts):
    job, volume_info, base = load_job(opts["report"])
    scene_job, medium = job["scene"], job.get("medium", {})
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # The job's own mesh: the grids of a .vdb lie where the file puts them,
    # around the mesh it was written for (docs/blender.md).
    meshes = import_mesh(resolve(base, scene_job.get("mesh", "")), bool(scene_job.get("flat_normals", False)))
    volume_obj = None
    if medium.get("volume"):
        if medium.get("ks") is not None or medium.get("contrast") is not None:
            raise JobError("the job overrides the volume's k_s or contrast, but the .vdb's sigma grids hold its own; "
                           "write a volume with them (jaderender volume) and import that")
        z_up = volume_info.get("vdb_up_axis", "y") == "z"
        volume_obj = import_volume(resolve(base, medium["volume"]), z_up)
    elif "sigma_s" not in medium or "sigma_a" not in medium:
        raise JobError("the job's medium has neither a volume nor sigma_s and sigma_a")
    build_materials(job, meshes, volume_obj, opts["step_rate"])
    camera = job.get("camera", {})
    width = opts["width"] or int(camera.get("width", 512))
    height = opts["height"] or int(camera.get("height", 512))
    add_camera(camera, width, height)
    add_sun(job.get("lights", {}), scene_job.get("boundary", "split"))
    add_world(job.get("lights", {}), base)
    settings = job.get("settings", {})
    set_film(job, opts["samples"] or int(settings.get("spp", 256)),
             opts["seed"] if opts["seed"] is not None else int(settings.get("seed", 1)))


def main():
    opts = parse_args(sys.argv)
    build_scene(opts)
    scene = bpy.context.scene
    if opts["save"]:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(opts["save"]))
        print("wrote " + opts["save"])
    if opts["render"] or opts["exr"]:
        render(scene, opts["render"], opts["exr"])


if __name__ == "__main__":
    try:
        main()
    except JobError as e:
        print("jaderender_blender: " + str(e), file=sys.stderr)
        if bpy.app.background:
            sys.exit(2)
