// Project Settings > Plugins > patchex. Each setting is the default of a console variable of the
// same meaning (r.Patchex.*), which can still be changed at run time. The defaults are patchex's
// own (PATCHEX_DEFAULT_* in patchex.h), set in the constructor.
#pragma once

#include "CoreMinimal.h"
#include "Engine/DeveloperSettings.h"
#include "PatchexSettings.generated.h"

UENUM()
enum class EPatchexWarp : uint8
{
	/** Joint bilateral gather guided by the target's G-buffer (the default, the most accurate). */
	GBufferGuided = 0,
	/** Plain motion-vector reprojection: cheapest, ghosts at disocclusions. */
	MotionVector = 1,
	/** Occlusion motion vectors: repairs most of the ghosting for a little more time. */
	OcclusionMotionVector = 2,
};

UCLASS(Config = Engine, DefaultConfig, meta = (DisplayName = "patchex"))
class UPatchexSettings : public UDeveloperSettings
{
	GENERATED_BODY()

public:
	UPatchexSettings();
	virtual FName GetCategoryName() const override { return TEXT("Plugins"); }
	virtual void PostInitProperties() override;
#if WITH_EDITOR
	virtual void PostEditChangeProperty(FPropertyChangedEvent& Event) override;
#endif

	/** r.Patchex.Enable: every second frame is extrapolated instead of lit (Vulkan RHI only). */
	UPROPERTY(Config, EditAnywhere, Category = "Frame generation")
	bool bEnable = false;

	/** r.Patchex.Preset: 0 = warp only, the one preset this version of patchex has. */
	UPROPERTY(Config, EditAnywhere, Category = "Frame generation", meta = (ClampMin = 0, ClampMax = 0))
	int32 Preset = 0;

	/** r.Patchex.Warp */
	UPROPERTY(Config, EditAnywhere, Category = "Warp")
	EPatchexWarp Warp = EPatchexWarp::GBufferGuided;

	/** r.Patchex.KernelRadius: gather radius of the G-buffer-guided warp, in pixels. */
	UPROPERTY(Config, EditAnywhere, Category = "Warp", meta = (ClampMin = 0, ClampMax = 3))
	int32 KernelRadius = 0;

	/** r.Patchex.GrowthX: k_x of the foveated segmentation (near-background margin per pixel of motion). */
	UPROPERTY(Config, EditAnywhere, Category = "Segmentation", meta = (ClampMin = 0.0, ClampMax = 64.0))
	float GrowthX = 0.0f;

	/** r.Patchex.GrowthY: k_y, as k_x vertically. */
	UPROPERTY(Config, EditAnywhere, Category = "Segmentation", meta = (ClampMin = 0.0, ClampMax = 64.0))
	float GrowthY = 0.0f;

private:
	void ApplyToConsoleVariables() const;
};
