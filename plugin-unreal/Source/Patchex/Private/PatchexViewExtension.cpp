#include "PatchexViewExtension.h"

#include "DataDrivenShaderPlatformInfo.h"
#include "GlobalShader.h"
#include "HAL/IConsoleManager.h"
#include "IVulkanDynamicRHI.h"
#include "PostProcess/PostProcessInputs.h"
#include "RenderGraphUtils.h"
#include "SceneRendering.h"
#include "SceneTextureParameters.h"
#include "ShaderParameterStruct.h"

// ---- Console variables (their defaults come from Project Settings > Plugins > patchex) ----

static TAutoConsoleVariable<int32> CVarEnable(TEXT("r.Patchex.Enable"), 0,
	TEXT("1: generate every second frame with patchex (Vulkan RHI only)."), ECVF_RenderThreadSafe);
static TAutoConsoleVariable<int32> CVarPreset(TEXT("r.Patchex.Preset"), PATCHEX_PRESET_WARP_ONLY,
	TEXT("patchex preset, PATCHEX_PRESET_* (0: warp only, 1: with the inpainting networks; 2 and 3 add the shadow sub-task, which this plugin does not feed yet). Applied when the context is created."), ECVF_RenderThreadSafe);
static TAutoConsoleVariable<int32> CVarWarp(TEXT("r.Patchex.Warp"), PATCHEX_WARP_GBUFFER_GUIDED,
	TEXT("0: G-buffer-guided warp, 1: motion vectors, 2: occlusion motion vectors."), ECVF_RenderThreadSafe);
static TAutoConsoleVariable<int32> CVarKernelRadius(TEXT("r.Patchex.KernelRadius"), PATCHEX_DEFAULT_KERNEL_RADIUS,
	TEXT("Gather radius of the G-buffer-guided warp, 0 to 3 pixels."), ECVF_RenderThreadSafe);
static TAutoConsoleVariable<int32> CVarResample(TEXT("r.Patchex.Resample"), PATCHEX_RESAMPLE_CATMULL_ROM,
	TEXT("How the G-buffer-guided warp resamples static surfaces: 0 Catmull-Rom (sharper), 1 bilinear (cheaper)."), ECVF_RenderThreadSafe);
static TAutoConsoleVariable<float> CVarGrowthX(TEXT("r.Patchex.GrowthX"), PATCHEX_DEFAULT_GROWTH_X,
	TEXT("k_x of the foveated segmentation, 0 to 64."), ECVF_RenderThreadSafe);
static TAutoConsoleVariable<float> CVarGrowthY(TEXT("r.Patchex.GrowthY"), PATCHEX_DEFAULT_GROWTH_Y,
	TEXT("k_y of the foveated segmentation, 0 to 64."), ECVF_RenderThreadSafe);

// ---- Unreal's velocity buffer to patchex's motion vectors (Shaders/Private/PatchexMotionVectors.usf) ----

class FPatchexMotionVectorsCS final : public FGlobalShader
{
	DECLARE_GLOBAL_SHADER(FPatchexMotionVectorsCS);
	SHADER_USE_PARAMETER_STRUCT(FPatchexMotionVectorsCS, FGlobalShader);

	BEGIN_SHADER_PARAMETER_STRUCT(FParameters, )
		SHADER_PARAMETER_RDG_TEXTURE(Texture2D, SceneDepthTexture)
		SHADER_PARAMETER_RDG_TEXTURE(Texture2D, SceneVelocityTexture)
		SHADER_PARAMETER_RDG_TEXTURE_UAV(RWTexture2D<float2>, MotionVectors)
		SHADER_PARAMETER(FMatrix44f, ClipToPrevClip)
		SHADER_PARAMETER(FUintVector2, Extent)
		SHADER_PARAMETER_STRUCT_REF(FViewUniformShaderParameters, View)
	END_SHADER_PARAMETER_STRUCT()

	static bool ShouldCompilePermutation(const FGlobalShaderPermutationParameters& Parameters)
	{
		return IsVulkanPlatform(Parameters.Platform);
	}
};
IMPLEMENT_GLOBAL_SHADER(FPatchexMotionVectorsCS, "/Plugin/Patchex/Private/PatchexMotionVectors.usf", "MainCS", SF_Compute);

// ---- The pass that records patchex into the RHI's command buffer ----

BEGIN_SHADER_PARAMETER_STRUCT(FPatchexPassParameters, )
	RDG_TEXTURE_ACCESS(SceneColor, ERHIAccess::UAVCompute)  // read on frame t, written on a generated frame
	RDG_TEXTURE_ACCESS(SceneDepth, ERHIAccess::SRVCompute)
	RDG_TEXTURE_ACCESS(GBufferA, ERHIAccess::SRVCompute)  // world normal * 0.5 + 0.5
	RDG_TEXTURE_ACCESS(GBufferB, ERHIAccess::SRVCompute)  // R metallic, G specular, B roughness
	RDG_TEXTURE_ACCESS(GBufferC, ERHIAccess::SRVCompute)  // base colour
	RDG_TEXTURE_ACCESS(CustomDepth, ERHIAccess::SRVCompute)  // its stencil: the dynamic-object id
	RDG_TEXTURE_ACCESS(MotionVectors, ERHIAccess::SRVCompute)
END_SHADER_PARAMETER_STRUCT()

struct FPatchexFrameInputs
{
	bool bGenerated = false;
	bool bCameraCut = false;
	FIntPoint Extent;
	PatchexCamera Camera{};
	FRHITexture* SceneColor = nullptr;
	FRHITexture* SceneDepth = nullptr;
	FRHITexture* GBufferA = nullptr;
	FRHITexture* GBufferB = nullptr;
	FRHITexture* GBufferC = nullptr;
	FRHITexture* CustomDepth = nullptr;
	FRHITexture* MotionVectors = nullptr;
};

namespace
{
// The layouts Unreal's Vulkan RHI gives the accesses declared above inside the pass.
constexpr VkImageLayout kSampledLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
constexpr VkImageLayout kSampledDepthLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
constexpr VkImageLayout kStorageLayout = VK_IMAGE_LAYOUT_GENERAL;

PatchexImage Describe(FRHITexture* Texture, VkImageLayout Layout, VkImageView View = VK_NULL_HANDLE)
{
	PatchexImage Image{};
	if (!Texture)
	{
		return Image;
	}
	const FVulkanRHIImageViewInfo Info = GetIVulkanDynamicRHI()->RHIGetImageViewInfo(Texture);
	Image.image = Info.Image;
	Image.view = View != VK_NULL_HANDLE ? View : Info.ImageView;
	Image.format = Info.Format;
	Image.width = Info.Width;
	Image.height = Info.Height;
	Image.layout = Layout;
	if (EnumHasAnyFlags(Info.UEFlags, ETextureCreateFlags::ShaderResource))
	{
		Image.usage |= VK_IMAGE_USAGE_SAMPLED_BIT;
	}
	if (EnumHasAnyFlags(Info.UEFlags, ETextureCreateFlags::UAV))
	{
		Image.usage |= VK_IMAGE_USAGE_STORAGE_BIT;
	}
	return Image;
}

void CopyMatrix(const FMatrix& Matrix, float Out[16])
{
	// Unreal multiplies row vectors; the same memory read as columns is patchex's column-vector matrix.
	for (int32 Row = 0; Row < 4; ++Row)
	{
		for (int32 Column = 0; Column < 4; ++Column)
		{
			Out[Row * 4 + Column] = float(Matrix.M[Row][Column]);
		}
	}
}

/** patchex's camera of a view, its world shifted by -Origin so that float precision holds. */
PatchexCamera CameraOf(const FViewMatrices& Matrices, const FIntPoint& Extent, float NearPlane, const FVector& Origin)
{
	PatchexCamera Camera{};
	CopyMatrix(FTranslationMatrix(Origin) * Matrices.GetViewMatrix(), Camera.view);
	// Unreal's NDC has y up; patchex's (Vulkan's) y grows down the image.
	CopyMatrix(Matrices.GetProjectionMatrix() * FScaleMatrix(FVector(1.0, -1.0, 1.0)), Camera.projection);
	const FVector2D Jitter = Matrices.GetTemporalAAJitter();  // NDC units
	Camera.jitter[0] = float(0.5 * Jitter.X * Extent.X);
	Camera.jitter[1] = float(-0.5 * Jitter.Y * Extent.Y);
	Camera.near_plane = NearPlane;
	Camera.far_plane = INFINITY;  // Unreal's reversed-Z projection has an infinite far plane
	Camera.depth_convention = PATCHEX_DEPTH_HARDWARE_REVERSED;
	return Camera;
}
}  // namespace

FPatchexViewExtension::FPatchexViewExtension(const FAutoRegister& AutoRegister, const FPatchexApi& InApi)
	: FSceneViewExtensionBase(AutoRegister), Api(InApi)
{
}

FPatchexViewExtension::~FPatchexViewExtension()
{
	// The context and the views must outlive every command buffer that used them.
	ENQUEUE_RENDER_COMMAND(PatchexDestroy)([Api = Api, Context = Context, Views = AspectViews](FRHICommandListImmediate& RHICmdList)
	{
		RHICmdList.ImmediateFlush(EImmediateFlushType::FlushRHIThreadFlushResources);
		RHICmdList.EnqueueLambda([Api, Context, Views](FRHICommandListImmediate&)
		{
			IVulkanDynamicRHI* Vulkan = GetIVulkanDynamicRHI();
			VkDevice Device = Vulkan->RHIGetVkDevice();
			auto DestroyView = reinterpret_cast<PFN_vkDestroyImageView>(Vulkan->RHIGetVkDeviceProcAddr("vkDestroyImageView"));
			auto WaitIdle = reinterpret_cast<PFN_vkDeviceWaitIdle>(Vulkan->RHIGetVkDeviceProcAddr("vkDeviceWaitIdle"));
			WaitIdle(Device);
			for (const auto& View : Views)
			{
				DestroyView(Device, View.Value, nullptr);
			}
			if (Context)
			{
				Api.Destroy(Context);
			}
		});
	});
	FlushRenderingCommands();
}

bool FPatchexViewExtension::IsActiveThisFrame_Internal(const FSceneViewExtensionContext&) const
{
	return CVarEnable.GetValueOnAnyThread() != 0 && RHIGetInterfaceType() == ERHIInterfaceType::Vulkan;
}

bool FPatchexViewExtension::IsGenerated(uint32 FrameNumber) const
{
	return FrameNumber % 2 == 1;
}

void FPatchexViewExtension::SetupViewFamily(FSceneViewFamily& Family)
{
	if (!IsGenerated(Family.FrameNumber) || bRenderNext.exchange(false))
	{
		return;
	}
	// A generated frame: keep the G-buffers, skip what lights them; patchex writes its colour.
	FEngineShowFlags& Flags = Family.EngineShowFlags;
	Flags.SetDirectLighting(false);
	Flags.SetDynamicShadows(false);
	Flags.SetGlobalIllumination(false);
	Flags.SetLumenGlobalIllumination(false);
	Flags.SetLumenReflections(false);
	Flags.SetReflectionEnvironment(false);
	Flags.SetScreenSpaceReflections(false);
	Flags.SetAmbientOcclusion(false);
	Flags.SetVolumetricFog(false);
}

bool FPatchexViewExtension::EnsureContext(FIntPoint Extent)
{
	if (Context && Extent.X <= ContextExtent.X && Extent.Y <= ContextExtent.Y)
	{
		return true;
	}
	IVulkanDynamicRHI* Vulkan = GetIVulkanDynamicRHI();
	if (Context)
	{
		// Larger frames than the context was made for (a resolution change): start again.
		Api.Destroy(Context);
		Context = nullptr;
	}
	PatchexCreateInfo Info{};
	Info.header = {PATCHEX_STRUCT_TYPE_CREATE_INFO, sizeof(PatchexCreateInfo), nullptr};
	Info.instance = Vulkan->RHIGetVkInstance();
	Info.physical_device = Vulkan->RHIGetVkPhysicalDevice();
	Info.device = Vulkan->RHIGetVkDevice();
	Info.get_instance_proc_addr =
		reinterpret_cast<PFN_vkGetInstanceProcAddr>(Vulkan->RHIGetVkInstanceProcAddr("vkGetInstanceProcAddr"));
	Info.get_device_proc_addr = reinterpret_cast<PFN_vkGetDeviceProcAddr>(Vulkan->RHIGetVkInstanceProcAddr("vkGetDeviceProcAddr"));
	Info.queue_family_index = Vulkan->RHIGetGraphicsQueueFamilyIndex();
	Info.max_width = uint32(Extent.X);
	Info.max_height = uint32(Extent.Y);
	Info.frames_in_flight = 3;  // Unreal keeps up to three frames in flight
	Info.preset = uint32(CVarPreset.GetValueOnRenderThread());
	if (Api.Create(&Info, &Context) != PATCHEX_RESULT_SUCCESS)
	{
		UE_LOG(LogPatchex, Error, TEXT("patchex_create: %hs; frame generation is off"), Api.LastError(nullptr));
		CVarEnable->Set(0, ECVF_SetByCode);
		Context = nullptr;
		return false;
	}
	ContextExtent = Extent;
	SubmittedFrames = 0;
	return true;
}

VkImageView FPatchexViewExtension::AspectView(VkImage Image, VkFormat Format, VkImageAspectFlags Aspect)
{
	// Unreal's own views of a depth-stencil texture cover both aspects; patchex reads one.
	if (VkImageView* Found = AspectViews.Find({Image, Aspect}))
	{
		return *Found;
	}
	IVulkanDynamicRHI* Vulkan = GetIVulkanDynamicRHI();
	auto CreateView = reinterpret_cast<PFN_vkCreateImageView>(Vulkan->RHIGetVkDeviceProcAddr("vkCreateImageView"));
	VkImageViewCreateInfo Info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
	Info.image = Image;
	Info.viewType = VK_IMAGE_VIEW_TYPE_2D;
	Info.format = Format;
	Info.subresourceRange = {Aspect, 0, 1, 0, 1};
	VkImageView View = VK_NULL_HANDLE;
	if (CreateView(Vulkan->RHIGetVkDevice(), &Info, nullptr, &View) != VK_SUCCESS)
	{
		return VK_NULL_HANDLE;
	}
	AspectViews.Add({Image, Aspect}, View);
	return View;
}

void FPatchexViewExtension::Record(VkCommandBuffer CommandBuffer, const FPatchexFrameInputs& Frame)
{
	const PatchexImage Depth = Describe(Frame.SceneDepth, kSampledDepthLayout);
	const PatchexImage CustomDepth = Describe(Frame.CustomDepth, kSampledDepthLayout);
	PatchexGeometry Geometry{};
	Geometry.depth = Describe(Frame.SceneDepth, kSampledDepthLayout, AspectView(Depth.image, Depth.format, VK_IMAGE_ASPECT_DEPTH_BIT));
	Geometry.normal = Describe(Frame.GBufferA, kSampledLayout);
	Geometry.normal_encoding = PATCHEX_NORMAL_UNORM;
	Geometry.stencil = Frame.CustomDepth
		? Describe(Frame.CustomDepth, kSampledDepthLayout, AspectView(CustomDepth.image, CustomDepth.format, VK_IMAGE_ASPECT_STENCIL_BIT))
		: PatchexImage{};
	Geometry.motion_vectors = Describe(Frame.MotionVectors, kSampledLayout);
	Geometry.motion_vector_scale[0] = Geometry.motion_vector_scale[1] = 1.0f;
	Geometry.camera = Frame.Camera;

	const uint32 Family = GetIVulkanDynamicRHI()->RHIGetGraphicsQueueFamilyIndex();
	PatchexResult Result;
	if (!Frame.bGenerated)
	{
		PatchexFrameDesc Desc{};
		Desc.header = {PATCHEX_STRUCT_TYPE_FRAME_DESC, sizeof(PatchexFrameDesc), nullptr};
		Desc.frame_index = ++SubmittedFrames;
		Desc.reset = Frame.bCameraCut ? 1 : 0;
		Desc.queue_family_index = Family;
		Desc.width = uint32(Frame.Extent.X);
		Desc.height = uint32(Frame.Extent.Y);
		Desc.color = Describe(Frame.SceneColor, kStorageLayout);
		Desc.base_color = Describe(Frame.GBufferC, kSampledLayout);
		Desc.material = Describe(Frame.GBufferB, kSampledLayout);
		Desc.geometry = Geometry;
		Result = Api.SubmitGBuffers(Context, CommandBuffer, &Desc);
	}
	else
	{
		PatchexWarpSettings Warp{};
		Warp.header = {PATCHEX_STRUCT_TYPE_WARP_SETTINGS, sizeof(PatchexWarpSettings), nullptr};
		Warp.kind = uint32(CVarWarp.GetValueOnRenderThread());
		Warp.kernel_radius = uint32(CVarKernelRadius.GetValueOnRenderThread());
		Warp.sigma_spatial = PATCHEX_DEFAULT_SIGMA_SPATIAL;
		Warp.sigma_depth = PATCHEX_DEFAULT_SIGMA_DEPTH;
		Warp.sigma_normal = PATCHEX_DEFAULT_SIGMA_NORMAL;
		Warp.sigma_position = PATCHEX_DEFAULT_SIGMA_POSITION;
		Warp.occlusion_search_radius = PATCHEX_DEFAULT_OCCLUSION_SEARCH_RADIUS;
		Warp.hole_fill = PATCHEX_HOLE_FILL_BACKGROUND;
		Warp.resample = uint32(CVarResample.GetValueOnRenderThread());
		PatchexSegmentationSettings Segmentation{};
		Segmentation.header = {PATCHEX_STRUCT_TYPE_SEGMENTATION_SETTINGS, sizeof(PatchexSegmentationSettings), &Warp};
		Segmentation.growth_x = CVarGrowthX.GetValueOnRenderThread();
		Segmentation.growth_y = CVarGrowthY.GetValueOnRenderThread();

		PatchexExtrapolateDesc Desc{};
		Desc.header = {PATCHEX_STRUCT_TYPE_EXTRAPOLATE_DESC, sizeof(PatchexExtrapolateDesc), &Segmentation};
		Desc.queue_family_index = Family;
		Desc.alpha = 0.5f;  // halfway between two rendered frames
		Desc.width = uint32(Frame.Extent.X);
		Desc.height = uint32(Frame.Extent.Y);
		Desc.base_color = Describe(Frame.GBufferC, kSampledLayout);
		Desc.material = Describe(Frame.GBufferB, kSampledLayout);
		Desc.geometry = Geometry;
		Desc.output = Describe(Frame.SceneColor, kStorageLayout);
		Result = Api.Extrapolate(Context, CommandBuffer, &Desc);
		if (Result == PATCHEX_RESULT_RENDER_INSTEAD)
		{
			bRenderNext = true;
		}
	}
	if (Result < 0)
	{
		UE_LOG(LogPatchex, Warning, TEXT("patchex: %hs"), Api.LastError(Context));
	}
	// patchex bound its own compute pipeline and descriptor sets: the RHI must not assume its own.
	GetIVulkanDynamicRHI()->RHIFinishExternalComputeWork(CommandBuffer);
}

void FPatchexViewExtension::PrePostProcessPass_RenderThread(
	FRDGBuilder& GraphBuilder, const FSceneView& View, const FPostProcessingInputs& Inputs)
{
	const FViewInfo& ViewInfo = static_cast<const FViewInfo&>(View);
	const FSceneTextureParameters SceneTextures = GetSceneTextureParameters(GraphBuilder, ViewInfo);
	FRDGTextureRef SceneColor = (*Inputs.SceneTextures)->SceneColorTexture;
	if (SceneColor->Desc.Format != PF_FloatRGBA)
	{
		UE_LOG(LogPatchex, Warning, TEXT("patchex needs r.SceneColorFormat=4 (RGBA16F); frame generation is off"));
		CVarEnable->Set(0, ECVF_SetByCode);
		return;
	}
	const FIntPoint Extent = SceneColor->Desc.Extent;
	if (!EnsureContext(Extent))
	{
		return;
	}

	// Motion vectors in pixels, to the previous frame, for every pixel.
	FRDGTextureRef MotionVectors = GraphBuilder.CreateTexture(
		FRDGTextureDesc::Create2D(Extent, PF_G16R16F, FClearValueBinding::None, TexCreate_ShaderResource | TexCreate_UAV),
		TEXT("Patchex.MotionVectors"));
	auto* Motion = GraphBuilder.AllocParameters<FPatchexMotionVectorsCS::FParameters>();
	Motion->SceneDepthTexture = SceneTextures.SceneDepthTexture;
	Motion->SceneVelocityTexture = SceneTextures.GBufferVelocityTexture;
	Motion->MotionVectors = GraphBuilder.CreateUAV(MotionVectors);
	Motion->ClipToPrevClip = FMatrix44f(ViewInfo.ViewMatrices.GetInvViewProjectionMatrix() *
		ViewInfo.PrevViewInfo.ViewMatrices.GetViewProjectionMatrix());
	Motion->Extent = FUintVector2(Extent.X, Extent.Y);
	Motion->View = ViewInfo.ViewUniformBuffer;
	FComputeShaderUtils::AddPass(GraphBuilder, RDG_EVENT_NAME("Patchex.MotionVectors"),
		TShaderMapRef<FPatchexMotionVectorsCS>(ViewInfo.ShaderMap), Motion, FComputeShaderUtils::GetGroupCount(Extent, 8));

	const bool bGenerated = IsGenerated(View.Family->FrameNumber) && SubmittedFrames > 0;
	if (!bGenerated)
	{
		Origin = ViewInfo.ViewMatrices.GetViewOrigin();
	}
	FPatchexFrameInputs Frame;
	Frame.bGenerated = bGenerated;
	Frame.bCameraCut = View.bCameraCut;
	Frame.Extent = Extent;
	Frame.Camera = CameraOf(ViewInfo.ViewMatrices, Extent, View.NearClippingDistance, Origin);

	auto* Parameters = GraphBuilder.AllocParameters<FPatchexPassParameters>();
	Parameters->SceneColor = SceneColor;
	Parameters->SceneDepth = SceneTextures.SceneDepthTexture;
	Parameters->GBufferA = SceneTextures.GBufferATexture;
	Parameters->GBufferB = SceneTextures.GBufferBTexture;
	Parameters->GBufferC = SceneTextures.GBufferCTexture;
	Parameters->CustomDepth = (*Inputs.SceneTextures)->CustomDepthTexture;
	Parameters->MotionVectors = MotionVectors;
	GraphBuilder.AddPass(RDG_EVENT_NAME("Patchex.%s", bGenerated ? TEXT("Extrapolate") : TEXT("Submit")), Parameters,
		ERDGPassFlags::Compute | ERDGPassFlags::NeverCull,
		[this, Parameters, Frame](FRHICommandListImmediate& RHICmdList) mutable
		{
			Frame.SceneColor = Parameters->SceneColor->GetRHI();
			Frame.SceneDepth = Parameters->SceneDepth->GetRHI();
			Frame.GBufferA = Parameters->GBufferA->GetRHI();
			Frame.GBufferB = Parameters->GBufferB->GetRHI();
			Frame.GBufferC = Parameters->GBufferC->GetRHI();
			Frame.CustomDepth = Parameters->CustomDepth ? Parameters->CustomDepth->GetRHI() : nullptr;
			Frame.MotionVectors = Parameters->MotionVectors->GetRHI();
			RHICmdList.EnqueueLambda([this, Frame](FRHICommandListImmediate&)
			{
				Record(GetIVulkanDynamicRHI()->RHIGetActiveVkCommandBuffer(), Frame);
			});
		});
}
