// SPDX-License-Identifier: MIT
/**
 * @file xs_camera.glsl
 * @brief Launch-to-pixel mapping (row interleave for lavapipe) and camera rays from xs_eye.
 * Requires xs_bindings.glsl.
 */
#ifndef XS_CAMERA_GLSL
#define XS_CAMERA_GLSL

/**
 * Pixel row of launch row r for an image of h rows: r / 2 for even r, h - 1 - r / 2 for odd r
 * (launch rows 0,1,2,3,... -> pixel rows 0, h-1, 1, h-2, ...). A bijection for any h (the even
 * launch rows cover rows 0..ceil(h/2)-1, the odd ones ceil(h/2)..h-1). lavapipe hands each
 * worker thread one contiguous block of workgroups; pairing top and bottom rows in every block
 * balances images whose top is cheap sky (DESIGN.md "Platform"). Images are unchanged: every
 * pixel is still computed once, from its own pixel coordinates.
 */
uint xs_pixel_row(uint r, uint h)
{
    return (r & 1u) == 0u ? (r >> 1u) : (h - 1u - (r >> 1u));
}

#ifndef XS_NO_TLAS /* ray-tracing stages only; compute shaders may use the camera rays */
/** Pixel of this invocation (x right, y down from the top row) and the eye (launch z). */
uvec3 xs_launch_pixel()
{
    uvec3 l = gl_LaunchIDEXT;
    return uvec3(l.x, xs_pixel_row(l.y, gl_LaunchSizeEXT.y), l.z);
}
#endif

struct xs_ray {
    vec3 origin;
    vec3 dir;        /* unit, world space */
    float depth_per_t; /* view-space depth along -Z per unit of t */
};

/**
 * Camera ray through the image position pos (pixels, (0,0) = top-left corner of the image).
 * Eye-space direction (mix(tanL, tanR, u), mix(tanU, tanD, v), -1) with u, v in [0,1] across
 * the image (v = 0 at the top), then rotated to world space by view_inv.
 */
xs_ray xs_camera_ray(uint eye, vec2 pos)
{
    xs_eye e = frame.eyes[eye];
    vec2 uv = pos / vec2(frame.width, frame.height);
    vec3 d_eye = vec3(mix(e.tan_fov.x, e.tan_fov.y, uv.x), mix(e.tan_fov.z, e.tan_fov.w, uv.y), -1.0);
    float len = length(d_eye);
    xs_ray r;
    r.origin = e.view_inv[3].xyz;
    r.dir = normalize(mat3(e.view_inv) * d_eye);
    r.depth_per_t = 1.0 / len;
    return r;
}

#endif
