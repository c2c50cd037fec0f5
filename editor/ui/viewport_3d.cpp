#include "editor/ui/viewport_3d.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <GLFW/glfw3.h>
#include <glm/gtc/type_ptr.hpp>
#include <imgui.h>

#include "editor/model/scene_preview.h"
#include "editor/model/terrain_mesh.h"
#include "editor/ui/gl.h"
#include "editor/ui/theme.h"
#include "graph/curves.h"
#include "graph/mesh.h"
#include "graph/points.h"

namespace orogen::editor {

namespace {

// Position, normal, sRGB colour per vertex; lit in linear space, a little haze with distance.
constexpr const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 color;
uniform mat4 view_projection;
uniform float vertical_scale;
uniform vec3 offset;
out vec3 v_normal;
out vec4 v_color;
out vec3 v_world;
void main() {
  vec3 p = position - offset;
  p.z *= vertical_scale;
  v_world = p;
  v_normal = normalize(vec3(normal.xy * vertical_scale, normal.z));
  v_color = color;
  gl_Position = view_projection * vec4(p, 1.0);
})";

// Instances: the class mesh's vertices through each instance's model matrix (translate * rotate * scale);
// normals by the inverse transpose, which for rotate * scale is the matrix divided by the squared scales.
constexpr const char* kInstancedVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 color;
layout(location = 3) in mat4 model;
uniform mat4 view_projection;
uniform float vertical_scale;
uniform vec3 offset;
out vec3 v_normal;
out vec4 v_color;
out vec3 v_world;
void main() {
  mat3 m = mat3(model);
  vec3 s2 = vec3(dot(m[0], m[0]), dot(m[1], m[1]), dot(m[2], m[2]));
  vec3 n = m * (normal / max(s2, vec3(1e-12)));
  vec3 p = (model * vec4(position, 1.0)).xyz - offset;
  p.z *= vertical_scale;
  v_world = p;
  v_normal = normalize(vec3(n.xy * vertical_scale, n.z));
  v_color = color;
  gl_Position = view_projection * vec4(p, 1.0);
})";

constexpr const char* kFragment = R"(#version 330 core
in vec3 v_normal;
in vec4 v_color;
in vec3 v_world;
uniform vec3 sun;
uniform vec3 eye;
uniform float haze_distance;
out vec4 frag;
void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 albedo = pow(v_color.rgb, vec3(2.2));
  float diffuse = max(dot(n, sun), 0.0);
  float sky = 0.5 + 0.5 * n.z;                       // hemisphere ambient
  vec3 lit = albedo * (0.85 * diffuse * vec3(1.0, 0.97, 0.9) + 0.28 * sky * vec3(0.75, 0.85, 1.0));
  float haze = clamp(length(v_world - eye) / haze_distance, 0.0, 1.0);
  lit = mix(lit, vec3(0.52, 0.62, 0.75), 0.35 * haze * haze);
  frag = vec4(pow(lit, vec3(1.0 / 2.2)), v_color.a);
})";

constexpr const char* kPointsVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 2) in vec4 color;
uniform mat4 view_projection;
uniform float vertical_scale;
uniform vec3 offset;
uniform float point_size;
out vec4 v_color;
void main() {
  vec3 p = position - offset;
  p.z *= vertical_scale;
  v_color = color;
  gl_Position = view_projection * vec4(p, 1.0);
  gl_PointSize = point_size;
})";

constexpr const char* kPointsFragment = R"(#version 330 core
in vec4 v_color;
out vec4 frag;
void main() {
  vec2 d = gl_PointCoord - vec2(0.5);
  if (dot(d, d) > 0.25) discard;
  frag = vec4(mix(v_color.rgb, vec3(0.0), smoothstep(0.12, 0.25, dot(d, d))), 1.0);
})";

unsigned compile(GLenum kind, const char* source) {
  const unsigned s = glCreateShader(kind);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  int ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("3D viewport shader: ") + log);
  }
  return s;
}

unsigned link(const char* vs, const char* fs) {
  const unsigned p = glCreateProgram();
  const unsigned v = compile(GL_VERTEX_SHADER, vs), f = compile(GL_FRAGMENT_SHADER, fs);
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  int ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("3D viewport program: ") + log);
  }
  return p;
}

void push_vertex(std::vector<float>& v, glm::vec3 p, glm::vec3 n, glm::vec4 c) {
  v.insert(v.end(), {p.x, p.y, p.z, n.x, n.y, n.z, c.r, c.g, c.b, c.a});
}

}  // namespace

Viewport3D::~Viewport3D() {
  release(terrain_);
  release(markers_);
  release(mesh_);
  release(ribbons_);
  release(water_);
  for (auto& i : instanced_) release(i);
  if (program_) glDeleteProgram(program_);
  if (instanced_program_) glDeleteProgram(instanced_program_);
  if (points_program_) glDeleteProgram(points_program_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (color_) glDeleteTextures(1, &color_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
}

void Viewport3D::release(Buffers& b) {
  if (b.vao) glDeleteVertexArrays(1, &b.vao);
  if (b.vbo) glDeleteBuffers(1, &b.vbo);
  if (b.ebo) glDeleteBuffers(1, &b.ebo);
  b = {};
}

void Viewport3D::upload(Buffers& b, const std::vector<float>& vertices, const std::vector<std::uint32_t>& indices) {
  if (!b.vao) {
    glGenVertexArrays(1, &b.vao);
    glGenBuffers(1, &b.vbo);
    glGenBuffers(1, &b.ebo);
  }
  glBindVertexArray(b.vao);
  glBindBuffer(GL_ARRAY_BUFFER, b.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(),
               GL_STATIC_DRAW);
  const GLsizei stride = 10 * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<void*>(6 * sizeof(float)));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)), indices.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  b.count = static_cast<int>(indices.empty() ? vertices.size() / 10 : indices.size());
}

void Viewport3D::release(Instanced& b) {
  release(b.mesh);
  if (b.instance_vbo) glDeleteBuffers(1, &b.instance_vbo);
  b = {};
}

void Viewport3D::upload_instances(Instanced& b, const std::vector<glm::mat4>& transforms) {
  if (!b.instance_vbo) glGenBuffers(1, &b.instance_vbo);
  glBindVertexArray(b.mesh.vao);
  glBindBuffer(GL_ARRAY_BUFFER, b.instance_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(transforms.size() * sizeof(glm::mat4)), transforms.data(),
               GL_STATIC_DRAW);
  // A mat4 attribute takes four locations, one column each, advancing once per instance.
  for (int c = 0; c < 4; ++c) {
    glEnableVertexAttribArray(static_cast<GLuint>(3 + c));
    glVertexAttribPointer(static_cast<GLuint>(3 + c), 4, GL_FLOAT, GL_FALSE, sizeof(glm::mat4),
                          reinterpret_cast<void*>(c * sizeof(glm::vec4)));
    glVertexAttribDivisor(static_cast<GLuint>(3 + c), 1);
  }
  glBindVertexArray(0);
  b.instances = static_cast<int>(transforms.size());
}

void Viewport3D::ensure_gl() {
  if (program_) return;
  program_ = link(kVertex, kFragment);
  points_program_ = link(kPointsVertex, kPointsFragment);
  instanced_program_ = link(kInstancedVertex, kFragment);
}

void Viewport3D::resize_target(int width, int height) {
  if (width == target_w_ && height == target_h_ && fbo_) return;
  if (!fbo_) {
    glGenFramebuffers(1, &fbo_);
    glGenTextures(1, &color_);
    glGenRenderbuffers(1, &depth_);
  }
  glBindTexture(GL_TEXTURE_2D, color_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glBindTexture(GL_TEXTURE_2D, 0);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  target_w_ = width;
  target_h_ = height;
}

void Viewport3D::update_geometry(const PreviewContent& content) {
  HeightfieldPtr field = content.backdrop;
  if (auto* h = std::get_if<HeightfieldPtr>(&content.value); h && *h) field = *h;
  // Rebuilt when the data change (same pointers: same immutable data; they are held so the addresses
  // cannot be reused meanwhile).
  const void* value_ptr = std::visit(
      [](const auto& v) -> const void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return nullptr;
        else
          return v.get();
      },
      content.value);
  char key[256];
  std::snprintf(key, sizeof key, "%p|%p|%p", value_ptr, static_cast<const void*>(field.get()),
                static_cast<const void*>(content.drape.get()));
  std::string full_key = key;
  if (content.scene) {
    // Every part of the scene (a new scene value whenever its instances or class meshes change).
    char part[64];
    std::snprintf(part, sizeof part, "|scene %p|%p", static_cast<const void*>(content.scene->scene.get()),
                  static_cast<const void*>(content.scene->terrain.get()));
    full_key += part;
  }
  if (geometry_key_ == full_key) return;
  geometry_key_ = full_key;
  shown_scene_ = content.scene;
  shown_value_ = content.value;
  shown_field_ = field;
  shown_drape_ = content.drape;
  bool have_bounds = false;
  glm::dvec3 lo(0.0), hi(0.0);
  auto extend = [&](glm::vec3 p) {
    lo = have_bounds ? glm::min(lo, glm::dvec3(p)) : glm::dvec3(p);
    hi = have_bounds ? glm::max(hi, glm::dvec3(p)) : glm::dvec3(p);
    have_bounds = true;
  };

  std::vector<float> vertices;
  auto upload_mesh = [&](Buffers& b, const TerrainMesh& tm) {
    vertices.clear();
    vertices.reserve(tm.positions.size() * 10);
    for (std::size_t k = 0; k < tm.positions.size(); ++k)
      push_vertex(vertices, tm.positions[k], tm.normals[k], tm.colors[k]);
    upload(b, vertices, tm.indices);
  };
  // Water depth stands on its terrain (the backdrop): the terrain is drawn, the water on it.
  HeightfieldPtr water_depth;
  if (auto* h = std::get_if<HeightfieldPtr>(&content.value);
      h && *h && content.kind == OutputKind::WaterDepth && content.backdrop) {
    water_depth = *h;
    field = content.backdrop;
  }
  double cell = 0.0;  // the terrain mesh's cell size (m)
  const ScenePreview* scene = content.scene ? &*content.scene : nullptr;
  if (scene && scene->terrain) {
    // The scene's own terrain mesh (what the file holds), tinted by height when it has no colours.
    const TerrainMesh tm = mesh_geometry(*scene->terrain, {.tint_uniform_by_height = true});
    upload_mesh(terrain_, tm);
    if (!tm.positions.empty()) {
      extend(tm.min);
      extend(tm.max);
    }
  } else if (field) {
    TerrainMeshOptions options;
    options.drape = content.drape.get();
    // A field that is not a height (a mask, a signed field) wears its kind's colours.
    const bool value_field = std::holds_alternative<HeightfieldPtr>(content.value) && !water_depth;
    const HeightfieldStyle style = style_for(value_field ? content.kind : OutputKind::Height);
    options.map = style.map;
    options.color_range = style_range(*field, style);
    const TerrainMesh tm = build_terrain_mesh(*field, options);
    upload_mesh(terrain_, tm);
    extend(tm.min);
    extend(tm.max);
    cell = std::max(field->domain.spacing.x, field->domain.spacing.y) *
           std::max(1.0, static_cast<double>(std::max(field->width(), field->height()) - 1) /
                             std::max(1, std::max(tm.columns, tm.rows) - 1));
  } else {
    terrain_.count = 0;
  }
  if (water_depth) {
    const TerrainMesh wm = build_water_mesh(*field, *water_depth);
    upload_mesh(water_, wm);
  } else {
    water_.count = 0;
  }
  if (auto* c = std::get_if<CurvesPtr>(&content.value); c && *c) {
    CurveRibbonOptions options;
    // At least a cell and a half of the terrain mesh wide, so every river stays visible; lifted a little
    // above the ground so the ribbon is not lost in it.
    options.min_width = static_cast<float>(1.5 * cell);
    const double relief = field ? static_cast<double>(value_range(*field).hi - value_range(*field).lo) : 0.0;
    options.lift = static_cast<float>(0.002 * relief);
    const TerrainMesh rm = build_curve_ribbons(**c, field.get(), options);
    upload_mesh(ribbons_, rm);
    if (!rm.positions.empty()) {
      extend(rm.min);
      extend(rm.max);
    }
  } else {
    ribbons_.count = 0;
  }

  for (auto& i : instanced_) release(i);
  instanced_.clear();
  scene_info_.clear();
  if (scene && scene->scene) {
    // Every class of the scene, its mesh at its instances; Instance's proxies in the class colours.
    const SceneClassInstances inst = build_instances(*scene->scene);
    std::vector<TerrainMesh> geometry;
    std::vector<const TerrainMesh*> meshes;
    geometry.reserve(inst.class_ids.size());
    int classes = 0, proxies = 0;
    for (std::size_t k = 0; k < inst.class_ids.size(); ++k) {
      const std::int32_t cls = inst.class_ids[k];
      const SceneClass& c = scene->scene->classes.at(cls);
      geometry.push_back(c.proxy ? proxy_geometry(class_color(cls)) : mesh_geometry(*c.mesh));
      if (inst.per_class[k].empty() || geometry.back().positions.empty()) continue;
      ++classes;
      proxies += c.proxy ? 1 : 0;
      Instanced b;
      upload_mesh(b.mesh, geometry.back());
      upload_instances(b, inst.per_class[k]);
      instanced_.push_back(b);
    }
    for (const auto& g : geometry) meshes.push_back(&g);
    // Framed on the terrain when there is one, so that editing the scatter does not move the camera.
    glm::vec3 ilo, ihi;
    if (terrain_.count == 0 && instance_bounds(inst, meshes, ilo, ihi)) {
      extend(ilo);
      extend(ihi);
    }
    scene_info_ = std::to_string(inst.count) + " instances of " + std::to_string(classes) +
                  (classes == 1 ? " class" : " classes");
    if (proxies > 0) scene_info_ += ", " + std::to_string(proxies) + " without a mesh as 1 m proxies";
  }

  vertices.clear();
  if (auto* p = std::get_if<PointsPtr>(&content.value); p && *p && !scene) {
    const Points& pts = **p;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      push_vertex(vertices, pts.position[k], {0, 0, 1}, marker_color(k < pts.class_id.size() ? pts.class_id[k] : 0));
      extend(pts.position[k]);
    }
    upload(markers_, vertices, {});
  } else {
    markers_.count = 0;
  }

  vertices.clear();
  if (auto* m = std::get_if<MeshPtr>(&content.value); m && *m) {
    const TerrainMesh tm = mesh_geometry(**m);
    upload_mesh(mesh_, tm);
    if (!tm.positions.empty()) {
      extend(tm.min);
      extend(tm.max);
    }
  } else {
    mesh_.count = 0;
  }
  if (have_bounds) {
    const bool changed =
        !framed_ || glm::length(lo - bounds_min_) + glm::length(hi - bounds_max_) > 1e-3 * glm::length(hi - lo);
    bounds_min_ = lo;
    bounds_max_ = hi;
    if (changed) framed_ = false;
    // An object on its own (a plant or rock mesh, no terrain under it) is first seen from the side.
    if (changed && !field && std::holds_alternative<MeshPtr>(content.value)) camera_.pitch = 0.2;
  }
}

void Viewport3D::render(int width, int height) {
  resize_target(width, height);
  GLint previous_fbo = 0, previous_viewport[4];
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &previous_fbo);
  glGetIntegerv(GL_VIEWPORT, previous_viewport);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width, height);
  glClearColor(0.50f, 0.60f, 0.72f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_CULL_FACE);

  // Geometry is drawn relative to the bounds' centre (float precision holds for large worlds), with heights
  // scaled; the camera lives in that space.
  const glm::dvec3 centre = (bounds_min_ + bounds_max_) * 0.5;
  const OrbitCamera& cam = camera_;
  const glm::mat4 vp = cam.projection(static_cast<double>(width) / height) * cam.view();
  const glm::vec3 offset(static_cast<float>(centre.x), static_cast<float>(centre.y), static_cast<float>(centre.z));
  const glm::vec3 sun = glm::normalize(glm::vec3(-0.45f, 0.35f, 0.62f));
  const glm::vec3 eye = glm::vec3(cam.eye());
  const float haze = static_cast<float>(std::max(cam.distance * 2.5, 1.0));

  glUseProgram(program_);
  glUniformMatrix4fv(glGetUniformLocation(program_, "view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
  glUniform1f(glGetUniformLocation(program_, "vertical_scale"), vertical_scale_);
  glUniform3fv(glGetUniformLocation(program_, "offset"), 1, glm::value_ptr(offset));
  glUniform3fv(glGetUniformLocation(program_, "sun"), 1, glm::value_ptr(sun));
  glUniform3fv(glGetUniformLocation(program_, "eye"), 1, glm::value_ptr(eye));
  glUniform1f(glGetUniformLocation(program_, "haze_distance"), haze);
  if (wireframe_) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  for (const Buffers* b : {&terrain_, &mesh_})
    if (b->count > 0) {
      glBindVertexArray(b->vao);
      glDrawElements(GL_TRIANGLES, b->count, GL_UNSIGNED_INT, nullptr);
    }
  if (!instanced_.empty()) {
    glUseProgram(instanced_program_);
    glUniformMatrix4fv(glGetUniformLocation(instanced_program_, "view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform1f(glGetUniformLocation(instanced_program_, "vertical_scale"), vertical_scale_);
    glUniform3fv(glGetUniformLocation(instanced_program_, "offset"), 1, glm::value_ptr(offset));
    glUniform3fv(glGetUniformLocation(instanced_program_, "sun"), 1, glm::value_ptr(sun));
    glUniform3fv(glGetUniformLocation(instanced_program_, "eye"), 1, glm::value_ptr(eye));
    glUniform1f(glGetUniformLocation(instanced_program_, "haze_distance"), haze);
    for (const Instanced& b : instanced_)
      if (b.mesh.count > 0 && b.instances > 0) {
        glBindVertexArray(b.mesh.vao);
        glDrawElementsInstanced(GL_TRIANGLES, b.mesh.count, GL_UNSIGNED_INT, nullptr, b.instances);
      }
    glUseProgram(program_);
  }
  if (wireframe_) glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  if (ribbons_.count > 0) {
    // Rivers lie on the terrain: pulled towards the eye in depth so they win against the ground they follow.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-2.0f, -4.0f);
    glBindVertexArray(ribbons_.vao);
    glDrawElements(GL_TRIANGLES, ribbons_.count, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }
  if (water_.count > 0) {
    // Translucent water after everything opaque, tested against the terrain (which cuts the shoreline) but
    // not writing depth; the target's alpha stays opaque.
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glDepthMask(GL_FALSE);
    glBindVertexArray(water_.vao);
    glDrawElements(GL_TRIANGLES, water_.count, GL_UNSIGNED_INT, nullptr);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  if (markers_.count > 0) {
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(points_program_);
    glUniformMatrix4fv(glGetUniformLocation(points_program_, "view_projection"), 1, GL_FALSE, glm::value_ptr(vp));
    glUniform1f(glGetUniformLocation(points_program_, "vertical_scale"), vertical_scale_);
    glUniform3fv(glGetUniformLocation(points_program_, "offset"), 1, glm::value_ptr(offset));
    glUniform1f(glGetUniformLocation(points_program_, "point_size"), marker_size_);
    glBindVertexArray(markers_.vao);
    glDrawArrays(GL_POINTS, 0, markers_.count);
    glDisable(GL_PROGRAM_POINT_SIZE);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(previous_fbo));
  glViewport(previous_viewport[0], previous_viewport[1], previous_viewport[2], previous_viewport[3]);
}

void Viewport3D::set_view(double yaw_deg, double pitch_deg, double zoom_notches) {
  camera_.yaw = yaw_deg * M_PI / 180.0;
  camera_.pitch = std::clamp(pitch_deg, -89.0, 89.0) * M_PI / 180.0;
  pending_zoom_ = zoom_notches;
  framed_ = false;
}

void Viewport3D::draw(const PreviewContent& content) {
  ImGui::SetNextItemWidth(140);
  ImGui::SliderFloat("##vscale", &vertical_scale_, 0.1f, 10.0f, "height x%.2f", ImGuiSliderFlags_Logarithmic);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Vertical exaggeration");
  ImGui::SameLine();
  ImGui::Checkbox("wireframe", &wireframe_);
  ImGui::SameLine();
  if (ImGui::Button("Frame")) framed_ = false;
  if (content.stale) {
    ImGui::SameLine();
    ImGui::TextColored(ImColor(theme::status_color(NodeRunState::Phase::Computing)), "updating");
  }
  if (!scene_info_.empty() && content.scene) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", scene_info_.c_str());
  }

  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 32.0f);
  size.y = std::max(size.y, 32.0f);
  try {
    ensure_gl();
    update_geometry(content);
  } catch (const std::exception& e) {
    ImGui::TextColored(ImColor(theme::kError), "%s", e.what());
    return;
  }
  if (terrain_.count == 0 && markers_.count == 0 && mesh_.count == 0 && ribbons_.count == 0 && instanced_.empty()) {
    ImGui::InvisibleButton("##empty3d", size);
    const ImVec2 o = ImGui::GetItemRectMin();
    const char* text = content.node.empty()       ? "Select a node to view it in 3D"
                       : !content.error.empty()   ? content.error.c_str()
                       : has_value(content.value) ? "Nothing to show in 3D for this output"
                                                  : "Waiting for the evaluation...";
    const ImVec2 ts = ImGui::CalcTextSize(text);
    ImGui::GetWindowDrawList()->AddRectFilled(o, ImGui::GetItemRectMax(), IM_COL32(22, 23, 26, 255));
    ImGui::GetWindowDrawList()->AddText({o.x + (size.x - ts.x) * 0.5f, o.y + (size.y - ts.y) * 0.5f}, theme::kTextDim,
                                        text);
    return;
  }
  if (!framed_) {
    const glm::dvec3 centre = (bounds_min_ + bounds_max_) * 0.5;
    const glm::dvec3 lo = (bounds_min_ - centre) * glm::dvec3(1, 1, vertical_scale_);
    const glm::dvec3 hi = (bounds_max_ - centre) * glm::dvec3(1, 1, vertical_scale_);
    camera_.frame(lo, hi, static_cast<double>(size.x) / size.y);
    framed_ = true;
    if (pending_zoom_ != 0.0 && !geometry_key_.empty()) {
      camera_.zoom(pending_zoom_);
      pending_zoom_ = 0.0;
    }
  }

  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton(
      "##viewport3d", size,
      ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight | ImGuiButtonFlags_MouseButtonMiddle);
  const ImGuiIO& io = ImGui::GetIO();
  if (ImGui::IsItemActive()) {
    const glm::dvec2 d{io.MouseDelta.x, io.MouseDelta.y};
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left))
      camera_.orbit({d.x, d.y});
    else
      camera_.pan(d, size.y);
  }
  if (ImGui::IsItemHovered()) {
    if (io.MouseWheel != 0.0f) camera_.zoom(io.MouseWheel);
    if (ImGui::IsKeyPressed(GLFW_KEY_F, false) && !io.WantTextInput) framed_ = false;
  }
  const int w = std::max(1, static_cast<int>(size.x * io.DisplayFramebufferScale.x));
  const int h = std::max(1, static_cast<int>(size.y * io.DisplayFramebufferScale.y));
  render(w, h);
  // The framebuffer's rows start at the bottom: flip v.
  ImGui::GetWindowDrawList()->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(color_)), origin,
                                       {origin.x + size.x, origin.y + size.y}, {0, 1}, {1, 0});
}

}  // namespace orogen::editor
