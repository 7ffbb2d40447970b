// The mesh renderer's shaders: the camera-locked environments (reflection stripes at infinity,
// isophotes, highlight lines), the lights (Lambert, Blinn-Phong) and the scalar colour map, as
// GLSL 4.50 source.
#include "render/mesh_shaders.h"

namespace flexure::render {

// Vertex stage: frame coordinates in, clip coordinates out; the corner's barycentric coordinate
// (1 at its own corner, 0 at the others) comes from gl_VertexID, three corners per triangle.
const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in float scalar;
layout(location = 3) in float material;  // the material + 4 × the face's crack bits
uniform mat4 frameToClip;
out vec3 framePosition;
out vec3 frameNormal;
out float vertexScalar;
out float vertexMaterial;
out vec3 barycentric;
flat out int faceCracks;
void main() {
  framePosition = position;
  faceCracks = int(material + 0.5) / 4;
  vertexMaterial = material - 4.0 * float(faceCracks);
  frameNormal = normal;
  vertexScalar = scalar;
  barycentric = vec3(0.0);
  barycentric[gl_VertexID % 3] = 1.0;
  gl_Position = frameToClip * vec4(position, 1.0);
}
)";

// Fragment stage, in the camera-aligned frame (x right, y up, z toward the viewer). n is the unit
// normal flipped toward the front on back faces; v the unit vector toward the viewer: (0, 0, 1)
// for orthographic views, (eye − x)/|eye − x| for perspective. d = (−sin θ, cos θ, 0) is the unit
// vector across the stripes, θ the stripe angle in the image.
//
//  reflection  the view ray reflected about the normal, r = reflect(−v, n) = −v + 2 (n·v) n,
//              looks up a camera-locked environment of parallel stripes at infinity: stripe
//              coordinate s = N/2 · (r·d + 1), so the N stripes span r·d ∈ [−1, 1]. A plane seen
//              head-on reflects the single direction r = v ⟂ d: one colour.
//  isophote    bands of the diffuse term: s = N/2 · (n·L + 1), L the unit light direction.
//  highlight   highlight lines (Beier & Chen 1994): a family of parallel linear lights in the
//              plane z = h (h = 2, in front of the unit ball), running along the stripe angle and
//              spaced 2/N apart. The normal line x + λ n meets that plane at q = x + (h − x_z)/n_z
//              n; s = N/2 · (q·d). Dark lines where the normal line passes a light (s near an
//              integer); grey where n_z <= 0 (the normal line misses the plane).
//  shaded      Lambert plus a Blinn-Phong highlight: c (0.15 + 0.85 max(n·L, 0)) + 0.25 (n·H)^40.
//  scalar      (error, curvature, displacement) the interpolated vertex scalar through the
//              colour map on [lo, hi], unlit so that the colour reads as a value; with the zero
//              contour, black where |s| < 0.75 fwidth(s), fading out by 1.25 fwidth(s) (a line
//              about two pixels wide along the level set s = 0).
//  obstacle    (material 1, every style) Lambert in the obstacle colour: c (0.3 + 0.7 max(n·L, 0)).
//  marked      (material 2, a face RenderOptions.markedFaces names, every style) Lambert in the
//              marking colour, brighter: c (0.55 + 0.45 max(n·L, 0)), so that it reads as that
//              colour.
//  cracks      (the mesh's faces, every style) the crack colour, unlit, where the distance in
//              pixels to one of the face's crack edges or crack vertices is below the crack width,
//              blended over one pixel. With b the barycentric coordinates (affine across the face
//              on the screen, ∇ their pixel derivatives): to the edge opposite corner k, b_k /
//              |∇b_k|; to corner k, |G⁻¹ (b_i, b_j)| with G the rows ∇b_i, ∇b_j of the other two
//              corners (both vanish at corner k).
//
// Stripes are dark where s is within w/2 of an integer (w = the dark fraction of a period); the
// edges are smoothed over one pixel, |∇s| ≈ fwidth(s), against aliasing. The edge overlay paints
// blue the pixels within about one pixel of a triangle edge (a barycentric coordinate near 0).
const char* const kStripeFunctions = R"(
const vec3 darkStripeColour = vec3(0.06);
const vec3 lightStripeColour = vec3(0.96);
const vec3 surfaceColour = vec3(0.72, 0.77, 0.86);

// 1 on a dark stripe, 0 on a light one: the stripes are the bands of width stripeWidth (a
// fraction of the period) centred on the integers of s, antialiased over one pixel.
float darkStripe(float s) {
  float distanceToLine = abs(s - floor(s + 0.5));
  float halfPixel = 0.5 * max(fwidth(s), 1e-6);
  return 1.0 - smoothstep(0.5 * stripeWidth - halfPixel, 0.5 * stripeWidth + halfPixel,
                          distanceToLine);
}

// The styles' colours at the unit normal n seen along v (towards the eye), in eye coordinates.
// Reflection lines: s = N/2 (r·d + 1), r = reflect(−v, n) the view ray reflected in the surface,
// d = (stripeAcross, 0) the camera-locked direction across the stripes.
vec3 reflectionLines(vec3 n, vec3 v) {
  vec3 r = reflect(-v, n);
  float s = 0.5 * stripeCount * (dot(r, vec3(stripeAcross, 0.0)) + 1.0);
  return mix(lightStripeColour, darkStripeColour, darkStripe(s));
}
// Isophotes: s = N/2 (n·l + 1), bands of equal diffuse light from the direction l.
vec3 isophotes(vec3 n) {
  float s = 0.5 * stripeCount * (dot(n, lightDirection) + 1.0);
  return mix(lightStripeColour, darkStripeColour, darkStripe(s));
}
// Shaded: Lambert (15 % ambient) plus a Blinn–Phong highlight of exponent 40.
vec3 shaded(vec3 n, vec3 v) {
  vec3 halfway = normalize(lightDirection + v);
  return surfaceColour * (0.15 + 0.85 * max(dot(n, lightDirection), 0.0)) +
         vec3(0.25 * pow(max(dot(n, halfway), 0.0), 40.0));
}
)";

const char* const kFragmentShader = R"(#version 450 core
in vec3 framePosition;
in vec3 frameNormal;
in float vertexScalar;
in float vertexMaterial;
in vec3 barycentric;
flat in int faceCracks;
uniform int style;  // 0 reflection, 1 isophote, 2 highlight, 3 shaded, 4 scalar
uniform int perspective;
uniform vec3 eye;
uniform vec3 lightDirection;
uniform vec2 stripeAcross;
uniform float stripeCount;
uniform float stripeWidth;
uniform int edges;
uniform vec2 scalarRange;
uniform int stopCount;
uniform vec3 stops[16];
uniform int zeroContour;
uniform vec3 obstacleColour;
uniform vec3 markedColour;
uniform vec3 crackColour;
uniform float crackWidth;
out vec4 colour;

const vec3 edgeColour = vec3(0.15, 0.35, 0.85);  // visible on black and on white stripes
@STRIPE_FUNCTIONS@

vec3 colourMap(float value) {
  float t = clamp((value - scalarRange.x) / (scalarRange.y - scalarRange.x), 0.0, 1.0);
  float x = t * float(stopCount - 1);
  int i = min(int(floor(x)), stopCount - 2);
  return mix(stops[i], stops[i + 1], x - float(i));
}

// c with the face's cracks drawn over it (compiled in with CRACKS only); bx, by the pixel
// derivatives of the barycentric coordinates, taken on a face with cracks (faceCracks and the
// material are one value over a face, so the branches are the same across each 2 × 2 pixel quad
// the derivatives difference).
vec3 withCracks(vec3 c) {
#ifdef CRACKS
  if (faceCracks == 0) return c;
  vec3 bx = dFdx(barycentric), by = dFdy(barycentric);
  float nearest = 1e30;
  for (int k = 0; k < 3; ++k) {
    if ((faceCracks & (1 << k)) != 0)
      nearest = min(nearest, barycentric[k] / max(length(vec2(bx[k], by[k])), 1e-9));
    if ((faceCracks & (8 << k)) == 0) continue;
    int i = (k + 1) % 3, j = (k + 2) % 3;
    mat2 g = mat2(bx[i], bx[j], by[i], by[j]);  // columns: rows ∇b_i, ∇b_j
    if (abs(determinant(g)) > 1e-12)
      nearest = min(nearest, length(inverse(g) * vec2(barycentric[i], barycentric[j])));
  }
  c = mix(crackColour, c, smoothstep(crackWidth - 0.5, crackWidth + 0.5, nearest));
#endif
  return c;
}

void main() {
  vec3 n = normalize(frameNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = perspective != 0 ? normalize(eye - framePosition) : vec3(0.0, 0.0, 1.0);
  vec3 d = vec3(stripeAcross, 0.0);
  vec3 c;
  if (vertexMaterial > 1.5) {
    c = markedColour * (0.55 + 0.45 * max(dot(n, lightDirection), 0.0));
    colour = vec4(withCracks(c), 1.0);
    return;
  }
  if (vertexMaterial > 0.5) {
    colour = vec4(obstacleColour * (0.3 + 0.7 * max(dot(n, lightDirection), 0.0)), 1.0);
    return;
  }
  if (style == 0) {
    c = reflectionLines(n, v);
  } else if (style == 1) {
    c = isophotes(n);
  } else if (style == 2) {
    const float h = 2.0;
    if (n.z > 1e-3) {
      vec3 q = framePosition + (h - framePosition.z) / n.z * n;
      c = mix(lightStripeColour, darkStripeColour, darkStripe(0.5 * stripeCount * dot(q, d)));
    } else {
      c = vec3(0.5);
    }
  } else if (style == 3) {
    c = shaded(n, v);
  } else {
    c = colourMap(vertexScalar);
    if (zeroContour != 0) {
      float pixel = max(fwidth(vertexScalar), 1e-30);
      c = mix(vec3(0.0), c, smoothstep(0.75 * pixel, 1.25 * pixel, abs(vertexScalar)));
    }
  }
  if (edges != 0) {
    vec3 nearEdge = smoothstep(vec3(0.0), 1.2 * fwidth(barycentric), barycentric);
    c = mix(edgeColour, c, min(nearEdge.x, min(nearEdge.y, nearEdge.z)));
  }
  colour = vec4(withCracks(clamp(c, 0.0, 1.0)), 1.0);
}
)";

}  // namespace flexure::render
