"""The operator: the active object dents the selected mesh objects."""

import bpy
import numpy as np
from mathutils import Vector
from bpy.props import BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty

from . import contact, meshdata


def dentbend_module():
    """The dentbend package (bundled as a wheel with the extension), or None."""
    try:
        import dentbend
    except ImportError:
        return None
    return dentbend


class OBJECT_OT_dentbend_dent(bpy.types.Operator):
    """Dent the selected mesh objects with the active object, moved into them along its local
    -Z (or a direction you choose)"""

    bl_idname = "object.dentbend_dent"
    bl_label = "Dent (dentbend)"
    bl_options = {"REGISTER", "UNDO"}

    depth: FloatProperty(
        name="Depth",
        description="How deep the dent goes at its deepest, past the first contact",
        default=0.05,
        min=1e-6,
        soft_max=1.0,
        unit="LENGTH",
    )
    smoothing: FloatProperty(
        name="Smoothing",
        description="Width of the dent's smoothing (0: half the depth)",
        default=0.0,
        min=0.0,
        soft_max=1.0,
        unit="LENGTH",
    )
    preserve_volume: BoolProperty(
        name="Keep Volume",
        description="Raise a rim around the dent that puts its volume back",
        default=False,
    )
    refine: BoolProperty(
        name="Refine",
        description="Add vertices where the mesh is too coarse for the dent (new vertices "
        "interpolate UVs, colours and other attributes)",
        default=True,
    )
    direction: EnumProperty(
        name="Direction",
        description="Which way the active object moves into the others",
        items=(
            ("LOCAL_NEG_Z", "Local -Z", "Along the active object's local -Z axis"),
            ("CUSTOM", "Custom", "Along the direction below (world coordinates)"),
        ),
        default="LOCAL_NEG_Z",
    )
    custom_direction: FloatVectorProperty(
        name="Custom Direction",
        description="The direction the active object moves in, world coordinates",
        default=(0.0, 0.0, -1.0),
        subtype="DIRECTION",
        size=3,
    )

    @classmethod
    def poll(cls, context):
        active = context.active_object
        if context.mode != "OBJECT" or active is None or active.type != "MESH":
            cls.poll_message_set("Needs a mesh as the active object, in Object Mode")
            return False
        if not any(o is not active and o.type == "MESH" for o in context.selected_objects):
            cls.poll_message_set("Select the mesh objects to dent, then the one that dents them")
            return False
        return True

    def draw(self, _context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "depth")
        layout.prop(self, "smoothing")
        layout.prop(self, "preserve_volume")
        layout.prop(self, "refine")
        layout.prop(self, "direction")
        if self.direction == "CUSTOM":
            layout.prop(self, "custom_direction", text="")

    def move_direction(self, active):
        """The unit direction the active object moves in, world coordinates; None if zero."""
        if self.direction == "CUSTOM":
            d = np.array(self.custom_direction, dtype=np.float64)
        else:
            d = np.array(active.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0)), dtype=np.float64)
        length = float(np.linalg.norm(d))
        return d / length if length > 0.0 and np.isfinite(length) else None

    def execute(self, context):
        dentbend = dentbend_module()
        if dentbend is None:
            self.report({"ERROR"}, "The dentbend Python package is missing: reinstall the extension")
            return {"CANCELLED"}
        active = context.active_object
        direction = self.move_direction(active)
        if direction is None:
            self.report({"ERROR"}, "The direction is zero: choose a direction")
            return {"CANCELLED"}
        depsgraph = context.evaluated_depsgraph_get()
        projectile = meshdata.evaluated_world_mesh(active, depsgraph)
        if len(projectile[1]) == 0:
            self.report({"ERROR"}, f"{active.name} has no faces to dent with")
            return {"CANCELLED"}
        dented, deepest, seen = [], 0.0, {active.data.as_pointer()}
        for target in context.selected_objects:
            if target is active or target.type != "MESH":
                continue
            problem = self.refusal(target, seen)
            if problem:
                self.report({"WARNING"}, problem)
                continue
            seen.add(target.data.as_pointer())
            try:
                depth = self.dent_one(dentbend, target, projectile, direction)
            except dentbend.DentError as error:
                self.report({"WARNING"}, f"{target.name}: {error}")
                continue
            if depth is None:
                self.report({"WARNING"}, f"{target.name}: {active.name} does not reach it moving that way")
                continue
            dented.append(target.name)
            deepest = max(deepest, depth)
        if not dented:
            self.report({"WARNING"}, "Nothing was dented")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Dented {', '.join(dented)}: {deepest:.4g} m deep at most")
        return {"FINISHED"}

    @staticmethod
    def refusal(target, seen):
        """Why ``target`` cannot be dented as it is (its fix named), or None."""
        if target.data.shape_keys is not None:
            return f"{target.name} has shape keys, which a dent cannot carry: apply or remove them first"
        if target.data.as_pointer() in seen:
            return (
                f"{target.name} shares its mesh with the active object or an object dented already: "
                "make it single user first"
            )
        if len(target.data.polygons) == 0:
            return f"{target.name} has no faces"
        if abs(np.linalg.det(np.array(target.matrix_world, dtype=np.float64)[:3, :3])) < 1e-12:
            return f"{target.name} is scaled to zero along an axis: give it a non-zero scale"
        return None

    def dent_one(self, dentbend, target, projectile, direction):
        """Dents one object; returns the deepest displacement (m), or None when the active
        object never touches it."""
        world = np.array(target.matrix_world, dtype=np.float64)
        source = meshdata.Triangulated(target, world)
        positions, triangles = projectile
        relative = (positions - source.origin).astype(np.float32)
        found = contact.first_contact(source.relative, source.world_triangles, relative, triangles, direction)
        if found is None:
            return None
        travel, point = found
        at_contact = (relative.astype(np.float64) + travel * direction).astype(np.float32)
        result = dentbend.dent(
            source.relative,
            source.world_triangles,
            at_contact,
            triangles,
            point,
            direction,
            direction,
            self.depth,
            preserve_volume=self.preserve_volume,
            refine="auto" if self.refine else "off",
            sigma=self.smoothing if self.smoothing > 0.0 else None,
        )
        local = source.to_local(result.positions, result.moved)
        if len(result.positions) == len(source.local) and np.array_equal(result.faces, source.world_triangles):
            meshdata.write_positions(target.data, local)
        else:
            meshdata.rebuild(target, source, result, local)
        return float(result.max_displacement)
