#include "app/gl/imgui_renderer.h"

#include <glad/gl.h>
#include <imgui.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "app/gl/program.h"
#include "app/gl/shaders.h"

namespace gs::gl {

namespace {

void upload_font_atlas(GLuint texture) {
  ImGuiIO& io = ImGui::GetIO();
  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(intptr_t(texture)));
}

// ImDrawVert: pos (2 floats), uv (2 floats), col (4 bytes, normalised).
void describe_vertices() {
  const auto offset = [](size_t bytes) { return reinterpret_cast<const void*>(bytes); };
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert),
                        offset(offsetof(ImDrawVert, pos)));
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert),
                        offset(offsetof(ImDrawVert, uv)));
  glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(ImDrawVert),
                        offset(offsetof(ImDrawVert, col)));
}

}  // namespace

ImGuiRenderer::ImGuiRenderer()
    : program_(std::make_unique<Program>("imgui", shaders::imgui_vert, shaders::imgui_frag)) {
  ImGuiIO& io = ImGui::GetIO();
  io.BackendRendererName = "gridscope_gl33";
  io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;  // we draw with a base vertex
  projection_ = program_->uniform("projection");
  atlas_ = program_->uniform("atlas");
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glGenBuffers(1, &ebo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);  // recorded in the VAO
  describe_vertices();
  glBindVertexArray(0);
  glGenTextures(1, &font_);
  upload_font_atlas(font_);
}

ImGuiRenderer::~ImGuiRenderer() {
  glDeleteTextures(1, &font_);
  glDeleteBuffers(1, &ebo_);
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
}

// ImGui's colours are straight alpha; its expected blend keeps the destination opaque.
void ImGuiRenderer::set_state(const ImDrawData* data) {
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glEnable(GL_SCISSOR_TEST);
  const float fb_width = data->DisplaySize.x * data->FramebufferScale.x;
  const float fb_height = data->DisplaySize.y * data->FramebufferScale.y;
  glViewport(0, 0, GLsizei(fb_width), GLsizei(fb_height));
  // Orthographic: display pixels (top-left origin) to clip space.
  const float l = data->DisplayPos.x, r = l + data->DisplaySize.x;
  const float t = data->DisplayPos.y, b = t + data->DisplaySize.y;
  const float ortho[16] = {
      2.0f / (r - l),    0, 0, 0, 0, 2.0f / (t - b), 0, 0, 0, 0, -1, 0, (r + l) / (l - r),
      (t + b) / (b - t), 0, 1};
  glUseProgram(program_->id());
  glUniform1i(atlas_, 0);
  glUniformMatrix4fv(projection_, 1, GL_FALSE, ortho);
  glActiveTexture(GL_TEXTURE0);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);  // not part of the VAO's state
}

void ImGuiRenderer::draw(const ImDrawData* data) {
  const float fb_height = data->DisplaySize.y * data->FramebufferScale.y;
  if (data->DisplaySize.x <= 0 || fb_height <= 0) return;  // minimised window
  set_state(data);
  const ImVec2 origin = data->DisplayPos, scale = data->FramebufferScale;
  const GLenum index_type = sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
  for (int n = 0; n < data->CmdListsCount; ++n) {
    const ImDrawList* list = data->CmdLists[n];
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(list->VtxBuffer.Size) * GLsizeiptr(sizeof(ImDrawVert)),
                 list->VtxBuffer.Data, GL_STREAM_DRAW);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 GLsizeiptr(list->IdxBuffer.Size) * GLsizeiptr(sizeof(ImDrawIdx)),
                 list->IdxBuffer.Data, GL_STREAM_DRAW);
    for (const ImDrawCmd& cmd : list->CmdBuffer) {
      if (cmd.UserCallback) {
        if (cmd.UserCallback == ImDrawCallback_ResetRenderState)
          set_state(data);
        else
          cmd.UserCallback(list, &cmd);
        continue;
      }
      const float x0 = (cmd.ClipRect.x - origin.x) * scale.x;
      const float y0 = (cmd.ClipRect.y - origin.y) * scale.y;
      const float x1 = (cmd.ClipRect.z - origin.x) * scale.x;
      const float y1 = (cmd.ClipRect.w - origin.y) * scale.y;
      if (x1 <= x0 || y1 <= y0) continue;
      // GL's scissor box counts rows from the bottom.
      glScissor(GLint(x0), GLint(fb_height - y1), GLsizei(x1 - x0), GLsizei(y1 - y0));
      glBindTexture(GL_TEXTURE_2D, GLuint(reinterpret_cast<intptr_t>(cmd.TextureId)));
      glDrawElementsBaseVertex(
          GL_TRIANGLES, GLsizei(cmd.ElemCount), index_type,
          reinterpret_cast<const void*>(size_t(cmd.IdxOffset) * sizeof(ImDrawIdx)),
          GLint(cmd.VtxOffset));
    }
  }
  glBindVertexArray(0);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
}

namespace {

template <class T>
void append(std::vector<unsigned char>& bytes, const T* data, size_t count) {
  const auto* from = reinterpret_cast<const unsigned char*>(data);
  bytes.insert(bytes.end(), from, from + count * sizeof(T));
}
template <class T>
void append(std::vector<unsigned char>& bytes, const T& value) {
  append(bytes, &value, 1);
}

}  // namespace

bool DrawDataRecord::changed(const ImDrawData* data) {
  current_.clear();
  append(current_, data->DisplayPos);
  append(current_, data->DisplaySize);
  append(current_, data->FramebufferScale);
  append(current_, data->CmdListsCount);
  for (int n = 0; n < data->CmdListsCount; ++n) {
    const ImDrawList& list = *data->CmdLists[n];
    append(current_, list.CmdBuffer.Size);
    // Field by field: a command's padding bytes say nothing.
    for (const ImDrawCmd& cmd : list.CmdBuffer) {
      append(current_, cmd.ClipRect);
      append(current_, cmd.TextureId);
      append(current_, cmd.VtxOffset);
      append(current_, cmd.IdxOffset);
      append(current_, cmd.ElemCount);
      append(current_, cmd.UserCallback);
      append(current_, cmd.UserCallbackData);
    }
    append(current_, list.VtxBuffer.Size);
    append(current_, list.VtxBuffer.Data, size_t(list.VtxBuffer.Size));
    append(current_, list.IdxBuffer.Size);
    append(current_, list.IdxBuffer.Data, size_t(list.IdxBuffer.Size));
  }
  const bool same = current_ == recorded_;
  std::swap(current_, recorded_);
  return !same;
}

}  // namespace gs::gl
