# The README's Blender recipe, run headless by Blender itself (blender -b --python THIS -- OUT NAME
# FRAME): import OUT/frames/NAME/0000.obj with the importer's defaults (its texture coordinates
# come along), add a Mesh Cache modifier (PC2, default axes) on OUT/NAME.pc2, go to scene frame
# FRAME, and compare the evaluated mesh with that frame's OBJ (Blender is Z-up: the importer turns
# the object, so the file's (x, y, z) is the world's (x, -z, y)). Exit 0 when every vertex agrees
# to 1e-5 m (the cache's float32), 1 otherwise.
import sys

import bpy

out, name, frame = sys.argv[sys.argv.index("--") + 1:][:3]
frame = int(frame)
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath="%s/frames/%s/0000.obj" % (out, name))
ob = bpy.context.selected_objects[0]
uv_layers = len(ob.data.uv_layers)
cache = ob.modifiers.new("cache", 'MESH_CACHE')
cache.cache_format = 'PC2'
cache.filepath = "%s/%s.pc2" % (out, name)
bpy.context.scene.frame_set(frame)
mesh = ob.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
got = [ob.matrix_world @ v.co for v in mesh.vertices]
want = [[float(w) for w in line.split()[1:4]]
        for line in open("%s/frames/%s/%04d.obj" % (out, name, frame)) if line.startswith("v ")]
error = max(max(abs(g.x - w[0]), abs(g.y + w[2]), abs(g.z - w[1])) for g, w in zip(got, want))
print("blender: %s frame %d: %d vertices (the OBJ has %d), %d uv layers, largest difference %.3g m"
      % (name, frame, len(got), len(want), uv_layers, error))
sys.exit(0 if len(got) == len(want) and error < 1e-5 else 1)
