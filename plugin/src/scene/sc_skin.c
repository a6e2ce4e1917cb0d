// SPDX-License-Identifier: MIT
/**
 * @file sc_skin.c
 * @brief Skin and morph-target pose of the deformed meshes (glTF 2.0 §3.7.3, §3.8), and the
 *        CPU reference of the GPU deformation pass (shaders/deform.comp).
 */
#include "sc_scene.h"
#include "sc_xform.h"

#include <math.h>
#include <string.h>

/** Inverse of an affine column-major matrix (last row 0 0 0 1); identity when singular. */
static void affine_inverse(const float m[16], float out[16])
{
    float a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9];
    float g = m[2], h = m[6], i = m[10];
    float c00 = e * i - f * h, c01 = -(d * i - f * g), c02 = d * h - e * g;
    float det = a * c00 + b * c01 + c * c02;
    if (!(fabsf(det) > 1e-30f)) {
        sc_mat4_identity(out);
        return;
    }
    float r = 1.0f / det;
    /* inverse of the 3x3 = adjugate / det (rows of the adjugate are cofactor columns) */
    float inv[9] = {c00 * r, (c * h - b * i) * r, (b * f - c * e) * r,
                    c01 * r, (a * i - c * g) * r, (c * d - a * f) * r,
                    c02 * r, (b * g - a * h) * r, (a * e - b * d) * r};
    memset(out, 0, 16 * sizeof(float));
    for (int row = 0; row < 3; row++) {
        for (int col = 0; col < 3; col++)
            out[col * 4 + row] = inv[row * 3 + col];
        out[12 + row] =
            -(inv[row * 3] * m[12] + inv[row * 3 + 1] * m[13] + inv[row * 3 + 2] * m[14]);
    }
    out[15] = 1.0f;
}

void sc_scene_pose(sc_scene *s)
{
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        const sc_mesh *mesh = &s->meshes[m];
        if (mesh->deform_node == SC_NO_DEFORM)
            continue;
        const sc_node *n = &s->nodes[mesh->deform_node];
        if (mesh->skin_joint_count) {
            const sc_skin *sk = &s->skins[n->skin];
            float to_object[16], joint[16];
            affine_inverse(n->world, to_object);
            for (uint32_t j = 0; j < mesh->skin_joint_count; j++) {
                uint32_t at = sk->first_joint + j;
                sc_mat4_mul(s->nodes[s->skin_joints[at]].world, &s->inverse_binds[16 * at], joint);
                sc_mat4_mul(to_object, joint,
                            &s->pose_matrices[16 * (mesh->first_pose_matrix + j)]);
            }
        }
        for (uint32_t k = 0; k < mesh->target_count; k++)
            s->pose_weights[mesh->first_pose_weight + k] =
                k < n->weight_count ? s->node_weights[n->first_weight + k] : 0.0f;
    }
}

void sc_scene_posed_vertex(const sc_scene *s, uint32_t mi, uint32_t v, float out_pos[3],
                           float out_normal[3])
{
    const sc_mesh *mesh = &s->meshes[mi];
    const sc_vertex *rest = &s->vertices[v];
    uint32_t local = v - mesh->first_vertex;
    float p[3], n[3];
    memcpy(p, rest->position, sizeof p);
    memcpy(n, rest->normal, sizeof n);
    for (uint32_t k = 0; k < mesh->target_count; k++) {
        float w = s->pose_weights[mesh->first_pose_weight + k];
        const sc_morph_delta *d = &s->deltas[mesh->first_delta + k * mesh->vertex_count + local];
        for (int c = 0; c < 3; c++)
            p[c] += w * d->position[c], n[c] += w * d->normal[c];
    }
    /* The joint matrices are blended first, then applied, as deform.comp does. */
    float m[16] = {0};
    if (mesh->skin_sets == 0)
        sc_mat4_identity(m);
    for (uint32_t set = 0; set < mesh->skin_sets; set++) {
        const sc_skin_influence *in =
            &s->influences[mesh->first_influence + set * mesh->vertex_count + local];
        for (int i = 0; i < 4; i++) {
            if (in->weights[i] == 0.0f)
                continue;
            const float *J = &s->pose_matrices[16 * (mesh->first_pose_matrix + in->joints[i])];
            for (int e = 0; e < 16; e++)
                m[e] += in->weights[i] * J[e];
        }
    }
    for (int r = 0; r < 3; r++) {
        out_pos[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
        if (out_normal)
            out_normal[r] = m[r] * n[0] + m[4 + r] * n[1] + m[8 + r] * n[2];
    }
}
