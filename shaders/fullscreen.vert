#version 450
// Built-in vertex stage of cmr::vk::FragmentPipeline.
//
// Draw with vkCmdDraw(cmd, 3, 1, 0, 0) and no vertex buffer: vertices 0, 1, 2
// become (-1,-1), (3,-1), (-1,3) in clip space, one triangle whose clipped
// area is exactly the viewport, so every pixel runs the fragment shader once
// (no diagonal seam as with two triangles).

void main() {
    vec2 corner = vec2(float((gl_VertexIndex & 1) << 2),   // 0, 4, 0
                       float((gl_VertexIndex & 2) << 1));  // 0, 0, 4
    gl_Position = vec4(corner - 1.0, 0.0, 1.0);
}
