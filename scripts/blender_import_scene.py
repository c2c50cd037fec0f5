# Imports an Orogen scene (.glb or .gltf from WriteScene) into Blender with its instances, also where Blender's
# glTF importer does not know EXT_mesh_gpu_instancing (Blender 3.4, Debian 12's): the file is imported without
# the extension, then every instanced class node is replaced by linked duplicates of its mesh, one per instance.
# Optionally renders a still with Cycles.
#
#   blender -b --python scripts/blender_import_scene.py -- scene.glb [render.png] [--save scene.blend]
#
# Orogen's root node turns its z-up world into glTF's y-up one and Blender's importer turns it back, so an
# instance's translation, rotation and scale (Orogen's: metres, z up) are its Blender world transform.
import json
import math
import os
import struct
import sys
import tempfile

import bpy
import numpy
from mathutils import Quaternion, Vector

# Debian 12's Blender 3.4 glTF importer still uses numpy.bool, which NumPy 1.24 removed: every glTF import
# fails with "module 'numpy' has no attribute 'bool'" until the alias is put back.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

EXT = "EXT_mesh_gpu_instancing"


def read_gltf(path):
    """The glTF JSON and its binary buffer (GLB's BIN chunk, or the first buffer's data URI)."""
    data = open(path, "rb").read()
    if data[:4] == b"glTF":
        length = struct.unpack_from("<I", data, 12)[0]
        doc = json.loads(data[20:20 + length])
        offset = 20 + length
        offset += (4 - offset % 4) % 4
        bin_length = struct.unpack_from("<I", data, offset)[0] if offset < len(data) else 0
        return doc, data[offset + 8:offset + 8 + bin_length]
    import base64
    doc = json.loads(data)
    uri = doc["buffers"][0]["uri"]
    return doc, base64.b64decode(uri.split(",", 1)[1])


def floats(doc, binary, index, width):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    values = struct.unpack_from("<%df" % (acc["count"] * width), binary, start)
    return [values[k * width:(k + 1) * width] for k in range(acc["count"])]


def import_scene(path):
    doc, binary = read_gltf(path)
    source = path
    if EXT in doc.get("extensionsRequired", []):
        # Blender's importer refuses a file requiring an extension it lacks: import a copy that only uses it.
        doc_copy = dict(doc)
        doc_copy["extensionsRequired"] = [e for e in doc["extensionsRequired"] if e != EXT]
        if not doc_copy["extensionsRequired"]:
            del doc_copy["extensionsRequired"]
        handle, source = tempfile.mkstemp(suffix=".glb")
        text = json.dumps(doc_copy).encode()
        text += b" " * ((4 - len(text) % 4) % 4)
        bin_chunk = binary + b"\0" * ((4 - len(binary) % 4) % 4)
        with os.fdopen(handle, "wb") as f:
            f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(bin_chunk)))
            f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
            f.write(struct.pack("<II", len(bin_chunk), 0x004E4942) + bin_chunk)
    bpy.ops.import_scene.gltf(filepath=source)
    if source != path:
        os.remove(source)
    placed = 0
    for node in doc["nodes"]:
        ext = node.get("extensions", {}).get(EXT)
        if not ext:
            continue
        prototype = bpy.data.objects[node["name"]]
        attrs = ext["attributes"]
        t = floats(doc, binary, attrs["TRANSLATION"], 3)
        r = floats(doc, binary, attrs["ROTATION"], 4)
        s = floats(doc, binary, attrs["SCALE"], 3)
        collection = bpy.data.collections.new(node["name"])
        bpy.context.scene.collection.children.link(collection)
        for k in range(len(t)):
            obj = bpy.data.objects.new("%s.%d" % (node["name"], k), prototype.data)  # linked: one mesh
            obj.location = Vector(t[k])
            obj.rotation_mode = "QUATERNION"
            obj.rotation_quaternion = Quaternion((r[k][3], r[k][0], r[k][1], r[k][2]))
            obj.scale = Vector(s[k])
            collection.objects.link(obj)
        bpy.data.objects.remove(prototype)
        placed += len(t)
    return placed


def largest_gap_to_terrain():
    """The largest vertical distance, in Blender's world, from an instance's base to the terrain under it."""
    terrain = bpy.data.objects.get("terrain")
    if terrain is None:
        return None
    bpy.context.view_layer.update()  # world matrices of the objects just made
    to_local = terrain.matrix_world.inverted()
    worst = 0.0
    for obj in bpy.data.objects:
        if obj.type != "MESH" or obj == terrain:
            continue
        base = obj.matrix_world.translation
        origin, down = to_local @ (base + Vector((0, 0, 1e5))), to_local.to_3x3() @ Vector((0, 0, -1))
        hit, where, _, _ = terrain.ray_cast(origin, down.normalized())
        if hit:
            worst = max(worst, abs((terrain.matrix_world @ where).z - base.z))
    return worst


def render(out_png):
    scene = bpy.context.scene
    terrain = bpy.data.objects.get("terrain")
    lo = Vector((math.inf,) * 3)
    hi = Vector((-math.inf,) * 3)
    for corner in terrain.bound_box:
        w = terrain.matrix_world @ Vector(corner)
        lo = Vector(map(min, lo, w))
        hi = Vector(map(max, hi, w))
    center, size = (lo + hi) / 2, max(hi.x - lo.x, hi.y - lo.y)
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.clip_end = size * 10
    scene.collection.objects.link(cam)
    cam.location = center + Vector((0.5 * size, -0.8 * size, 0.6 * size))
    cam.rotation_euler = (center - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 4.0
    sun.rotation_euler = (math.radians(50), 0, math.radians(35))
    scene.collection.objects.link(sun)
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
    scene.render.resolution_x, scene.render.resolution_y = 960, 600
    scene.render.filepath = out_png
    bpy.ops.render.render(write_still=True)


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not args:
        sys.exit("usage: blender -b --python blender_import_scene.py -- scene.glb [render.png] [--save file.blend]")
    save = None
    if "--save" in args:
        save = args[args.index("--save") + 1]
        del args[args.index("--save"):args.index("--save") + 2]
    for obj in list(bpy.data.objects):  # the default cube, camera and light
        bpy.data.objects.remove(obj)
    placed = import_scene(args[0])
    meshes = sum(1 for o in bpy.data.objects if o.type == "MESH")
    print("orogen: %d instances placed, %d mesh objects" % (placed, meshes))
    gap = largest_gap_to_terrain()
    if gap is not None:
        print("orogen: largest gap from an instance base to the terrain %.4f m" % gap)
    if len(args) > 1:
        render(args[1])
    if save:
        bpy.ops.wm.save_as_mainfile(filepath=save)


main()
