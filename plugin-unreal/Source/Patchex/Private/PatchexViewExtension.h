// The scene view extension that runs patchex inside Unreal's renderer.
//
// With r.Patchex.Enable=1 every second frame is generated: the game thread still ticks it (its
// camera and animation are real), the renderer still draws its G-buffers, but the lighting
// passes are switched off, and before post-processing patchex writes the frame's colour by
// extrapolating the last fully rendered frame. Both kinds of frame then go through the same
// post-processing, upscaler and UI.
#pragma once

#include "CoreMinimal.h"
#include "PatchexApi.h"
#include "SceneViewExtension.h"

#include <atomic>

DECLARE_LOG_CATEGORY_EXTERN(LogPatchex, Log, All);

class FPatchexViewExtension final : public FSceneViewExtensionBase
{
public:
	FPatchexViewExtension(const FAutoRegister& AutoRegister, const FPatchexApi& InApi);
	virtual ~FPatchexViewExtension() override;

	virtual void SetupViewFamily(FSceneViewFamily& Family) override;
	virtual void SetupView(FSceneViewFamily& Family, FSceneView& View) override {}
	virtual void BeginRenderViewFamily(FSceneViewFamily& Family) override {}
	virtual void PrePostProcessPass_RenderThread(
		FRDGBuilder& GraphBuilder, const FSceneView& View, const FPostProcessingInputs& Inputs) override;

protected:
	virtual bool IsActiveThisFrame_Internal(const FSceneViewExtensionContext& Context) const override;

private:
	bool IsGenerated(uint32 FrameNumber) const;
	/** Creates (or re-creates, larger) the context; render thread. */
	bool EnsureContext(FIntPoint Extent);
	void Record(VkCommandBuffer CommandBuffer, const struct FPatchexFrameInputs& Frame);
	VkImageView AspectView(VkImage Image, VkFormat Format, VkImageAspectFlags Aspect);
	void ReleaseViews();

	const FPatchexApi& Api;
	PatchexContext* Context = nullptr;
	FIntPoint ContextExtent = FIntPoint::ZeroValue;
	uint64 SubmittedFrames = 0;
	/** World origin of the submitted frame's matrices, reused for its target (large worlds). */
	FVector Origin = FVector::ZeroVector;
	/** Set when patchex asks for a frame to be rendered (a camera cut): the next one is. */
	std::atomic<bool> bRenderNext{true};
	/** Depth- and stencil-aspect views the plugin made of engine images, by image. */
	TMap<TPair<VkImage, VkImageAspectFlags>, VkImageView> AspectViews;
};
