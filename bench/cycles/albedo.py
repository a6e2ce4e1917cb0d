# SPDX-License-Identifier: MIT
"""Directional albedo of a rough (roughness 1) white-ish dielectric under the two material
models the comparison meets: glTF 2.0's fresnel_mix as xrsc evaluates it (xs_bsdf.glsl:
F * GGX specular + (1 - F) * base / pi, exact dielectric Fresnel at IOR 1.5) and Blender 3.4's
Principled BSDF v1 as its glTF importer sets it up (specular 0.5 = F0 0.04, roughness 1):
Burley's diffuse with retro-reflection, base / pi * (1 + (FD90 - 1) FL)(1 + (FD90 - 1) FV),
FD90 = 0.5 + 2 roughness cos^2(theta_d), weighted 1 (not 1 - F), plus the GGX specular layer.
Numerical quadrature over the hemisphere; python3 bench/cycles/albedo.py [base] [roughness].
"""
import sys

import numpy as np


def fresnel_dielectric(c, eta=1.5):
    g2 = eta * eta - 1.0 + c * c
    g = np.sqrt(np.maximum(g2, 0.0))
    a, b = (g - c) / (g + c), (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return 0.5 * a * a * (1.0 + b * b)


def ggx(wo, wi, alpha):
    h = wo + wi
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nh = h[..., 2]
    a2 = alpha * alpha
    d = a2 / (np.pi * (nh * nh * (a2 - 1.0) + 1.0) ** 2)

    def lam(z):
        t2 = (1.0 - z * z) / (z * z)
        return 0.5 * (-1.0 + np.sqrt(1.0 + a2 * t2))

    g2 = 1.0 / (1.0 + lam(wo[..., 2]) + lam(wi[..., 2]))
    return d * g2 / (4.0 * wo[..., 2] * wi[..., 2]), np.sum(wo * h, axis=-1)


def albedo(base, rough, theta_o, n=400):
    wo = np.array([np.sin(theta_o), 0.0, np.cos(theta_o)])
    th = (np.arange(n) + 0.5) / n * (np.pi / 2)
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    T, P = np.meshgrid(th, ph, indexing="ij")
    wi = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    dw = np.sin(T) * (np.pi / 2 / n) * (2 * np.pi / (2 * n))
    cos_i = wi[..., 2]
    spec, oh = ggx(np.broadcast_to(wo, wi.shape), wi, rough * rough)
    f = fresnel_dielectric(oh)
    gltf = f * spec + (1.0 - f) * base / np.pi
    fl, fv = (1 - cos_i) ** 5, (1 - wo[2]) ** 5
    fd90 = 0.5 + 2.0 * rough * oh * oh
    burley = base / np.pi * (1 + (fd90 - 1) * fl) * (1 + (fd90 - 1) * fv)
    # Principled v1's specular colour: F0 0.04 blended to white by the normalised Fresnel
    f0 = 0.04
    fn = (f - fresnel_dielectric(np.ones(1))) / (1.0 - fresnel_dielectric(np.ones(1)))
    principled = burley + (f0 * (1 - fn) + fn) * spec
    s = lambda v: float(np.sum(v * cos_i * dw))
    return s(gltf), s(principled), s(base / np.pi * np.ones_like(cos_i))


if __name__ == "__main__":
    base = float(sys.argv[1]) if len(sys.argv) > 1 else 0.8
    rough = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    print("theta_o  glTF(xrsc)  Principled-v1  Lambert   (base %g, roughness %g)" % (base, rough))
    for deg in (0, 30, 60, 75):
        g, p, l = albedo(base, rough, np.radians(deg))
        print("%5d    %.4f      %.4f         %.4f" % (deg, g, p, l))
