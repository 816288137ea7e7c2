"""dentbend for Blender: dent the selected mesh objects with the active object.

Object > Dent (dentbend), or ``bpy.ops.object.dentbend_dent()``: the active object moves into
the selected ones along its local -Z (or a direction you choose) until it touches them, then
dents each by the depth you set, smoothed and with the volume kept if you ask. UVs, colours and
every other attribute are kept; vertices the dent adds interpolate them. Undo restores the
meshes.
"""

import bpy

from .operator import OBJECT_OT_dentbend_dent


def menu_entry(self, _context):
    self.layout.separator()
    self.layout.operator(OBJECT_OT_dentbend_dent.bl_idname, text="Dent (dentbend)")


def register():
    bpy.utils.register_class(OBJECT_OT_dentbend_dent)
    bpy.types.VIEW3D_MT_object.append(menu_entry)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(menu_entry)
    bpy.utils.unregister_class(OBJECT_OT_dentbend_dent)
