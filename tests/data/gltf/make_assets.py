# Makes the committed glTF test assets with Blender (Debian's blender 3.4, glTF exporter
# io_scene_gltf2), once; the outputs in this folder are what the tests read.
#
#   blender -b --factory-startup --python tests/data/gltf/make_assets.py -- tests/data/gltf
#
# scenes/maps/torus_mirrored.gltf (the bundled scenes/gltf_torus.json) is a copy of this
# folder's torus_mirrored.gltf.
#
# Blender computes every TANGENT (MikkTSpace, Mesh.calc_tangents) and writes it as the asset
# ships it: an independent implementation pgt's own MikkTSpace is checked against. Meshes are
# triangulated first, so that Blender's MikkTSpace sees the triangles the glTF holds.
import math
import os
import sys

import bmesh
import bpy

out = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else "."


def clear():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def triangulate(obj, smooth=True):
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.to_mesh(obj.data)
    bm.free()
    for poly in obj.data.polygons:
        poly.use_smooth = smooth


def export(obj, name, obj_too=False):
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.export_scene.gltf(
        filepath=os.path.join(out, name + ".gltf"),
        export_format="GLTF_EMBEDDED",
        use_selection=True,
        export_texcoords=True,
        export_normals=True,
        export_tangents=True,
        export_materials="NONE",
        export_yup=True,
        export_apply=True,
    )
    if obj_too:
        # World positions in Blender's own axes (+Z up), which are pgt's.
        bpy.ops.wm.obj_export(
            filepath=os.path.join(out, name + ".obj"),
            export_selected_objects=True,
            forward_axis="Y",
            up_axis="Z",
            export_normals=False,
            export_materials=False,
            export_uv=True,
        )


# A UV sphere, moved, turned and scaled, so that its glTF carries a node transform (the OBJ
# holds the transformed positions).
clear()
bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=0.5)
sphere = bpy.context.active_object
triangulate(sphere)
sphere.location = (0.1, -0.2, 0.05)
sphere.rotation_euler = (0.0, 0.0, math.radians(30))
sphere.scale = (1.0, 1.0, 0.8)
export(sphere, "sphere", obj_too=True)

# A torus whose left half has its UVs mirrored in u: handedness w = -1 there.
clear()
bpy.ops.mesh.primitive_torus_add(major_segments=24, minor_segments=8, major_radius=0.5,
                                 minor_radius=0.2)
torus = bpy.context.active_object
triangulate(torus)
uv = torus.data.uv_layers.active.data
for poly in torus.data.polygons:
    if poly.center.x < 0:
        for li in poly.loop_indices:
            uv[li].uv.x = -uv[li].uv.x
export(torus, "torus_mirrored")

# A cylinder with flat caps and smooth sides (split normals at the rims).
clear()
bpy.ops.mesh.primitive_cylinder_add(vertices=12, radius=0.4, depth=0.8)
cylinder = bpy.context.active_object
triangulate(cylinder)
for poly in cylinder.data.polygons:
    poly.use_smooth = abs(poly.normal.z) < 0.5
cylinder.data.use_auto_smooth = True
export(cylinder, "cylinder")
