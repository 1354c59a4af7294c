// The example engine's UI pass, run on every frame it shows, after patchex: tone-maps the
// pre-UI HDR colour into the display image and draws the HUD over it: a white bar across the
// top whose length is the shown instant's position in the animation's loop. patchex extrapolates
// the scene without the UI, and the UI is drawn for the instant shown, so it never smears or
// lags.
#version 450

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba16f) uniform readonly image2D scene_color;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D display;

layout(push_constant) uniform Hud {
  // Pixels of the bar, from the left edge.
  uint bar_length;
}
hud;

const int BAR_TOP = 2;
const int BAR_HEIGHT = 4;

void main() {
  ivec2 size = imageSize(display);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size))) return;
  vec3 color = imageLoad(scene_color, p).rgb;
  vec4 shown = vec4(color / (1.0 + color), 1.0);
  if (p.y >= BAR_TOP && p.y < BAR_TOP + BAR_HEIGHT && uint(p.x) < hud.bar_length) shown = vec4(1.0);
  imageStore(display, p, shown);
}
