/* dent.c: the dentbend C API from C. A ball of radius 0.3 m hits a unit sphere on top at
 * 3 m/s; the sphere takes a dent up to 0.1 m deep. Then each kind of bad call is shown to fail
 * with a status and a message, changing nothing. Last, the same hit as a game reports it:
 * bodies keyed by the engine's ids, a step's contacts with both bodies' motion, the dent depth
 * earned from the impact speed. Exits 0 when everything behaves so.
 *
 *   cargo build --release -p dentbend-c
 *   cc -std=c99 -Wall -Wextra -Iintegrations/c/include integrations/c/examples/dent.c \
 *      target/release/libdentbend_c.a -lm -lpthread -ldl -o dent && ./dent
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dentbend.h"

#define SEGMENTS 32
#define RINGS 16
#define VERTICES (2 + (RINGS - 1) * SEGMENTS)
#define TRIANGLES (2 * SEGMENTS * (RINGS - 1))

static int failures = 0;

static void check(int ok, const char *what) {
    printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) failures++;
}

/* A UV sphere of `radius` at height `y`: poles first and last, rings between, triangles
 * counter-clockwise seen from outside. */
static DbMesh *sphere(float radius, float y) {
    static float positions[3 * VERTICES];
    static uint32_t indices[3 * TRIANGLES];
    const double pi = 3.14159265358979323846;
    size_t v = 0, t = 0;
    positions[v++] = 0.0f; positions[v++] = y + radius; positions[v++] = 0.0f;
    for (int i = 1; i < RINGS; i++) {
        double theta = pi * i / RINGS;
        for (int j = 0; j < SEGMENTS; j++) {
            double phi = 2.0 * pi * j / SEGMENTS;
            positions[v++] = (float)(radius * sin(theta) * cos(phi));
            positions[v++] = (float)(y + radius * cos(theta));
            positions[v++] = (float)(radius * sin(theta) * sin(phi));
        }
    }
    positions[v++] = 0.0f; positions[v++] = y - radius; positions[v++] = 0.0f;
    uint32_t bottom = VERTICES - 1;
#define RING(i, j) ((uint32_t)(1 + ((i) - 1) * SEGMENTS + ((j) % SEGMENTS)))
    for (int j = 0; j < SEGMENTS; j++) {
        indices[t++] = 0; indices[t++] = RING(1, j + 1); indices[t++] = RING(1, j);
        for (int i = 1; i + 1 < RINGS; i++) {
            uint32_t a = RING(i, j), b = RING(i, j + 1), c = RING(i + 1, j), d = RING(i + 1, j + 1);
            indices[t++] = a; indices[t++] = b; indices[t++] = d;
            indices[t++] = a; indices[t++] = d; indices[t++] = c;
        }
        indices[t++] = RING(RINGS - 1, j); indices[t++] = RING(RINGS - 1, j + 1); indices[t++] = bottom;
    }
    return db_mesh_new(positions, VERTICES, indices, TRIANGLES);
}

int main(void) {
    DbMesh *target = sphere(1.0f, 0.0f);
    DbMesh *ball = sphere(0.3f, 1.3f);
    check(target != NULL && ball != NULL, "two spheres made");
    if (target == NULL || ball == NULL) {
        printf("  %s\n", db_last_error());
        return 1;
    }
    check(db_mesh_vertex_count(target) == VERTICES && db_mesh_triangle_count(target) == TRIANGLES,
          "counts read back");

    DbImpact impact = {{0.0f, 1.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, {0.0f, -3.0f, 0.0f}};
    DbDentOptions options = db_dent_options_default(0.1f);
    DbDentReport report = {0};
    int status = db_dent_ex(target, ball, &impact, &options, &report);
    check(status == DB_OK, "the ball dents the sphere");
    if (status != DB_OK) printf("  %s\n", db_last_error());

    const float *p = db_mesh_positions(target);
    float top = p[1];
    printf("     top vertex at y = %.4f m, %zu vertices moved, deepest %.4f m\n", top,
           db_mesh_moved_count(target), report.max_displacement);
    check(top < 0.97f && top > 0.85f, "the top sinks by most of the 0.1 m dent");
    check(report.max_displacement > 0.05f && report.max_displacement <= 0.1001f, "the deepest move is at most 0.1 m");
    size_t moved = db_mesh_moved_count(target);
    const uint32_t *which = db_mesh_moved(target);
    check(moved > 0 && moved == report.moved_vertices + report.added_vertices && which[0] == 0,
          "the moved vertices are listed, the top first");

    /* Bad calls: a status, a message, nothing changed. */
    float before[3 * VERTICES];
    size_t count = db_mesh_vertex_count(target);
    memcpy(before, db_mesh_positions(target), sizeof(float) * 3 * (count < VERTICES ? count : VERTICES));

    check(db_dent(NULL, ball, &impact, 0.1f) == DB_ERR_NULL_POINTER && strlen(db_last_error()) > 0,
          "a null target is refused");
    check(db_dent(target, ball, NULL, 0.1f) == DB_ERR_NULL_POINTER, "a null impact is refused");
    check(db_dent(target, target, &impact, 0.1f) == DB_ERR_INVALID_ARGUMENT, "a mesh denting itself is refused");
    check(db_dent(target, ball, &impact, NAN) == DB_ERR_INVALID_ARGUMENT, "a NaN dent distance is refused");
    DbImpact nan_impact = impact;
    nan_impact.point[0] = NAN;
    check(db_dent(target, ball, &nan_impact, 0.1f) == DB_ERR_INVALID_ARGUMENT, "a NaN contact point is refused");
    printf("     (%s)\n", db_last_error());
    check(memcmp(before, db_mesh_positions(target), sizeof(float) * 3 * VERTICES) == 0,
          "the refused calls changed nothing");

    float tri[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
    uint32_t face[3] = {0, 1, 2};
    check(db_mesh_new(tri, 3, face, 1) == NULL, "a NaN coordinate is refused");
    tri[7] = 1.0f;
    uint32_t far_face[3] = {0, 1, 7};
    check(db_mesh_new(tri, 3, far_face, 1) == NULL, "an index out of range is refused");
    printf("     (%s)\n", db_last_error());
    check(db_mesh_new(NULL, 3, face, 1) == NULL, "null positions are refused");
    check(db_mesh_new(tri, (size_t)1 << 40, face, 1) == NULL, "an absurd count is refused");
    check(db_mesh_vertex_count(NULL) == 0 && db_mesh_positions(NULL) == NULL, "a null mesh reads as empty");

    /* A game's step: body 7 (a fixed sphere) dents 2 cm per m/s above 1 m/s, at most 15 cm;
     * body 8 (the ball, 2 kg) falls on it at 8 m/s. */
    DbMesh *fresh = sphere(1.0f, 0.0f);
    DbDamage *damage = db_damage_new();
    const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    DbDentSettings settings = db_dent_settings_default(1.0f, 0.02f, 0.15f);
    check(db_damage_add_body(damage, 7, fresh, identity, &settings) == DB_OK, "body 7 dents");
    check(db_damage_add_projectile(damage, 8) == DB_OK, "body 8 hits");
    float inverse_inertia = 1.0f / (0.4f * 2.0f * 0.3f * 0.3f);
    DbHit hit;
    memset(&hit, 0, sizeof hit);
    hit.target = 7;
    hit.projectile = 8;
    hit.point[1] = 1.0f;
    hit.normal[1] = -1.0f;
    hit.projectile_state.center_of_mass[1] = 1.3f;
    hit.projectile_state.linear_velocity[1] = -8.0f;
    hit.projectile_state.mass = 2.0f;
    hit.projectile_state.inverse_inertia[0] = inverse_inertia;
    hit.projectile_state.inverse_inertia[4] = inverse_inertia;
    hit.projectile_state.inverse_inertia[8] = inverse_inertia;
    hit.projectile_surface = ball;
    memcpy(hit.projectile_to_world, identity, sizeof identity); /* the ball's mesh is in world coordinates */
    status = db_damage_step(damage, &hit, 1);
    check(status == DB_OK, "the step dents body 7");
    if (status != DB_OK) printf("  %s\n", db_last_error());
    DbAppliedDent made;
    size_t moved_count = 0, vertex_count = 0;
    const float *body = db_damage_positions(damage, 7, &vertex_count);
    db_damage_moved(damage, 7, &moved_count);
    check(db_damage_dent_count(damage) == 1 && db_damage_dent(damage, 0, &made) == DB_OK && made.target == 7,
          "one dent, on body 7");
    printf("     earned %.3f m, made %.3f m, %zu vertices moved, top at y = %.4f m\n", made.dent_distance,
           made.depth_made, moved_count, body[1]);
    check(fabsf(made.dent_distance - 0.14f) < 1e-4f && moved_count > 0 && body[1] < 0.95f,
          "(8 - 1) m/s x 2 cm per m/s = 14 cm earned, the top sunk");
    hit.target = 99;
    check(db_damage_step(damage, &hit, 1) == DB_ERR_INVALID_ARGUMENT, "a hit on an unknown body is refused");
    printf("     (%s)\n", db_last_error());

    /* Body 7 also breaks now, within 0.5 m of a hit that removes more than 40 J (the ball's
     * 64 J does): the engine makes a body of each piece, placed by the fracture's to_world. */
    DbFractureSettings breaks = db_fracture_settings_default(8, 1, 0.5f, 40.0f, INFINITY);
    check(db_damage_set_fracture(damage, 7, &breaks) == DB_OK, "body 7 breaks");
    hit.target = 7;
    hit.point[0] = hit.projectile_state.center_of_mass[0] = hit.projectile_to_world[9] = 0.3f;
    hit.point[1] = sqrtf(1.0f - 0.09f) - 0.1f; /* on the dent's slope, just below the old surface */
    hit.projectile_state.center_of_mass[1] = hit.projectile_to_world[10] = hit.point[1] + 0.3f;
    status = db_damage_step(damage, &hit, 1);
    check(status == DB_OK && db_damage_fracture_count(damage) == 1, "a second hit breaks body 7");
    if (status != DB_OK) printf("  %s\n", db_last_error());
    DbFracture broken;
    memset(&broken, 0, sizeof broken);
    float piece_mass = 0.0f;
    if (db_damage_fracture(damage, 0, &broken) == DB_OK) {
        for (size_t k = 0; k < broken.piece_count; k++) {
            DbPiece piece;
            if (db_damage_piece(damage, 0, k, &piece) == DB_OK) piece_mass += piece.mass;
        }
    }
    printf("     %.1f J broke it: %zu pieces of %.1f kg together, the rest %.1f kg\n", broken.energy,
           broken.piece_count, piece_mass, broken.rest_mass);
    check(broken.body == 7 && !broken.whole && broken.piece_count > 0 && piece_mass > 0.0f && broken.rest_mass > 0.0f,
          "pieces broke loose; the rest stays body 7");
    db_damage_free(damage);
    db_mesh_free(fresh);

    db_mesh_free(target);
    db_mesh_free(ball);
    db_mesh_free(NULL);
    printf("%s\n", failures == 0 ? "all ok" : "failures");
    return failures == 0 ? 0 : 1;
}
