// OpenGL 4.5 core entry points as function pointers, loaded from whichever context API is current
// (EGL, OSMesa or GLFW). libepoxy cannot dispatch for OSMesa contexts, hence this small loader.
#pragma once

#include <GL/glcorearb.h>

#include <string>

namespace hemirad::gl {

// X(name, type): every GL function Hemirad calls, as hemirad::gl::name (glName in the API).
#define HEMIRAD_GL_FUNCTIONS(X)                                                                      \
    X(ActiveTexture, PFNGLACTIVETEXTUREPROC)                                                         \
    X(AttachShader, PFNGLATTACHSHADERPROC)                                                           \
    X(BindBuffer, PFNGLBINDBUFFERPROC)                                                               \
    X(BindBufferBase, PFNGLBINDBUFFERBASEPROC)                                                       \
    X(BindFramebuffer, PFNGLBINDFRAMEBUFFERPROC)                                                     \
    X(BindImageTexture, PFNGLBINDIMAGETEXTUREPROC)                                                   \
    X(BindRenderbuffer, PFNGLBINDRENDERBUFFERPROC)                                                   \
    X(BindTexture, PFNGLBINDTEXTUREPROC)                                                             \
    X(BindVertexArray, PFNGLBINDVERTEXARRAYPROC)                                                     \
    X(BlendColor, PFNGLBLENDCOLORPROC)                                                               \
    X(BlendFunc, PFNGLBLENDFUNCPROC)                                                                 \
    X(BlendFunci, PFNGLBLENDFUNCIPROC)                                                               \
    X(BlitFramebuffer, PFNGLBLITFRAMEBUFFERPROC)                                                     \
    X(BufferData, PFNGLBUFFERDATAPROC)                                                               \
    X(BufferStorage, PFNGLBUFFERSTORAGEPROC)                                                         \
    X(BufferSubData, PFNGLBUFFERSUBDATAPROC)                                                         \
    X(CheckFramebufferStatus, PFNGLCHECKFRAMEBUFFERSTATUSPROC)                                       \
    X(Clear, PFNGLCLEARPROC)                                                                         \
    X(ClearBufferData, PFNGLCLEARBUFFERDATAPROC)                                                     \
    X(ClearBufferSubData, PFNGLCLEARBUFFERSUBDATAPROC)                                               \
    X(ClearBufferfi, PFNGLCLEARBUFFERFIPROC)                                                         \
    X(ClearBufferfv, PFNGLCLEARBUFFERFVPROC)                                                         \
    X(ClearBufferuiv, PFNGLCLEARBUFFERUIVPROC)                                                       \
    X(ClearTexSubImage, PFNGLCLEARTEXSUBIMAGEPROC)                                                   \
    X(ClearColor, PFNGLCLEARCOLORPROC)                                                               \
    X(ClearDepth, PFNGLCLEARDEPTHPROC)                                                               \
    X(ClearStencil, PFNGLCLEARSTENCILPROC)                                                           \
    X(ClientWaitSync, PFNGLCLIENTWAITSYNCPROC)                                                       \
    X(ClipControl, PFNGLCLIPCONTROLPROC)                                                             \
    X(ColorMask, PFNGLCOLORMASKPROC)                                                                 \
    X(ColorMaski, PFNGLCOLORMASKIPROC)                                                               \
    X(CompileShader, PFNGLCOMPILESHADERPROC)                                                         \
    X(CopyImageSubData, PFNGLCOPYIMAGESUBDATAPROC)                                                   \
    X(CreateProgram, PFNGLCREATEPROGRAMPROC)                                                         \
    X(CreateShader, PFNGLCREATESHADERPROC)                                                           \
    X(CullFace, PFNGLCULLFACEPROC)                                                                   \
    X(DeleteBuffers, PFNGLDELETEBUFFERSPROC)                                                         \
    X(DeleteFramebuffers, PFNGLDELETEFRAMEBUFFERSPROC)                                               \
    X(DeleteProgram, PFNGLDELETEPROGRAMPROC)                                                         \
    X(DeleteQueries, PFNGLDELETEQUERIESPROC)                                                         \
    X(DeleteRenderbuffers, PFNGLDELETERENDERBUFFERSPROC)                                             \
    X(DeleteShader, PFNGLDELETESHADERPROC)                                                           \
    X(DeleteSync, PFNGLDELETESYNCPROC)                                                               \
    X(DeleteTextures, PFNGLDELETETEXTURESPROC)                                                       \
    X(DeleteVertexArrays, PFNGLDELETEVERTEXARRAYSPROC)                                               \
    X(DepthFunc, PFNGLDEPTHFUNCPROC)                                                                 \
    X(DepthMask, PFNGLDEPTHMASKPROC)                                                                 \
    X(Disable, PFNGLDISABLEPROC)                                                                     \
    X(Disablei, PFNGLDISABLEIPROC)                                                                   \
    X(DispatchCompute, PFNGLDISPATCHCOMPUTEPROC)                                                     \
    X(DispatchComputeIndirect, PFNGLDISPATCHCOMPUTEINDIRECTPROC)                                     \
    X(DrawArrays, PFNGLDRAWARRAYSPROC)                                                               \
    X(DrawArraysInstanced, PFNGLDRAWARRAYSINSTANCEDPROC)                                             \
    X(DrawBuffers, PFNGLDRAWBUFFERSPROC)                                                             \
    X(DrawElements, PFNGLDRAWELEMENTSPROC)                                                           \
    X(Enable, PFNGLENABLEPROC)                                                                       \
    X(EnableVertexAttribArray, PFNGLENABLEVERTEXATTRIBARRAYPROC)                                     \
    X(Enablei, PFNGLENABLEIPROC)                                                                     \
    X(FenceSync, PFNGLFENCESYNCPROC)                                                                 \
    X(Finish, PFNGLFINISHPROC)                                                                       \
    X(Flush, PFNGLFLUSHPROC)                                                                         \
    X(FramebufferRenderbuffer, PFNGLFRAMEBUFFERRENDERBUFFERPROC)                                     \
    X(FramebufferTexture, PFNGLFRAMEBUFFERTEXTUREPROC)                                               \
    X(FramebufferTexture2D, PFNGLFRAMEBUFFERTEXTURE2DPROC)                                           \
    X(FramebufferTextureLayer, PFNGLFRAMEBUFFERTEXTURELAYERPROC)                                     \
    X(FrontFace, PFNGLFRONTFACEPROC)                                                                 \
    X(GenBuffers, PFNGLGENBUFFERSPROC)                                                               \
    X(GenFramebuffers, PFNGLGENFRAMEBUFFERSPROC)                                                     \
    X(GenQueries, PFNGLGENQUERIESPROC)                                                               \
    X(GenRenderbuffers, PFNGLGENRENDERBUFFERSPROC)                                                   \
    X(GenTextures, PFNGLGENTEXTURESPROC)                                                             \
    X(GenVertexArrays, PFNGLGENVERTEXARRAYSPROC)                                                     \
    X(GetBufferSubData, PFNGLGETBUFFERSUBDATAPROC)                                                   \
    X(GetError, PFNGLGETERRORPROC)                                                                   \
    X(GetInteger64v, PFNGLGETINTEGER64VPROC)                                                         \
    X(GetIntegerv, PFNGLGETINTEGERVPROC)                                                             \
    X(GetProgramInfoLog, PFNGLGETPROGRAMINFOLOGPROC)                                                 \
    X(GetProgramiv, PFNGLGETPROGRAMIVPROC)                                                           \
    X(GetQueryObjectui64v, PFNGLGETQUERYOBJECTUI64VPROC)                                             \
    X(GetShaderInfoLog, PFNGLGETSHADERINFOLOGPROC)                                                   \
    X(GetShaderiv, PFNGLGETSHADERIVPROC)                                                             \
    X(GetString, PFNGLGETSTRINGPROC)                                                                 \
    X(GetStringi, PFNGLGETSTRINGIPROC)                                                               \
    X(GetTextureSubImage, PFNGLGETTEXTURESUBIMAGEPROC)                                               \
    X(GetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)                                               \
    X(LinkProgram, PFNGLLINKPROGRAMPROC)                                                             \
    X(MapBufferRange, PFNGLMAPBUFFERRANGEPROC)                                                       \
    X(MemoryBarrier, PFNGLMEMORYBARRIERPROC)                                                         \
    X(PixelStorei, PFNGLPIXELSTOREIPROC)                                                             \
    X(PolygonOffset, PFNGLPOLYGONOFFSETPROC)                                                         \
    X(QueryCounter, PFNGLQUERYCOUNTERPROC)                                                           \
    X(ReadBuffer, PFNGLREADBUFFERPROC)                                                               \
    X(ReadPixels, PFNGLREADPIXELSPROC)                                                               \
    X(RenderbufferStorage, PFNGLRENDERBUFFERSTORAGEPROC)                                             \
    X(Scissor, PFNGLSCISSORPROC)                                                                     \
    X(ScissorIndexed, PFNGLSCISSORINDEXEDPROC)                                                       \
    X(ShaderSource, PFNGLSHADERSOURCEPROC)                                                           \
    X(StencilFunc, PFNGLSTENCILFUNCPROC)                                                             \
    X(StencilMask, PFNGLSTENCILMASKPROC)                                                             \
    X(StencilOp, PFNGLSTENCILOPPROC)                                                                 \
    X(TexImage2D, PFNGLTEXIMAGE2DPROC)                                                               \
    X(TexImage3D, PFNGLTEXIMAGE3DPROC)                                                               \
    X(TexParameteri, PFNGLTEXPARAMETERIPROC)                                                         \
    X(TexStorage2D, PFNGLTEXSTORAGE2DPROC)                                                           \
    X(TexStorage3D, PFNGLTEXSTORAGE3DPROC)                                                           \
    X(TexSubImage2D, PFNGLTEXSUBIMAGE2DPROC)                                                         \
    X(Uniform1f, PFNGLUNIFORM1FPROC)                                                                 \
    X(Uniform1i, PFNGLUNIFORM1IPROC)                                                                 \
    X(Uniform1ui, PFNGLUNIFORM1UIPROC)                                                               \
    X(Uniform2f, PFNGLUNIFORM2FPROC)                                                                 \
    X(Uniform2ui, PFNGLUNIFORM2UIPROC)                                                               \
    X(Uniform3f, PFNGLUNIFORM3FPROC)                                                                 \
    X(Uniform4f, PFNGLUNIFORM4FPROC)                                                                 \
    X(UniformMatrix4fv, PFNGLUNIFORMMATRIX4FVPROC)                                                   \
    X(UseProgram, PFNGLUSEPROGRAMPROC)                                                               \
    X(VertexAttribIPointer, PFNGLVERTEXATTRIBIPOINTERPROC)                                           \
    X(VertexAttribPointer, PFNGLVERTEXATTRIBPOINTERPROC)                                             \
    X(Viewport, PFNGLVIEWPORTPROC)                                                                   \
    X(ViewportIndexedf, PFNGLVIEWPORTINDEXEDFPROC)

#define HEMIRAD_GL_DECLARE(name, type) extern type name;
HEMIRAD_GL_FUNCTIONS(HEMIRAD_GL_DECLARE)
#undef HEMIRAD_GL_DECLARE

using ProcLoader = void* (*)(const char* name);

/// Resolves every entry point through `loader` (eglGetProcAddress, OSMesaGetProcAddress,
/// glfwGetProcAddress). A later API joins only if it resolves every function to the same pointer
/// (EGL and GLFW under glvnd do; OSMesa does not). Throws hemirad::Error naming the first missing
/// or mismatching function.
void loadApi(ProcLoader loader, const char* apiName);

/// Throws hemirad::Error("<what>: GL error 0x...") if the context recorded an error.
void check(const char* what);

/// "4.5 (Core Profile) Mesa 22.3.6 | llvmpipe (LLVM 15.0.6, 256 bits)".
std::string describeContext();

}  // namespace hemirad::gl
