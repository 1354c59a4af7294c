#include "PatchexSettings.h"

#include "HAL/IConsoleManager.h"
#include "patchex.h"

UPatchexSettings::UPatchexSettings()
{
	KernelRadius = PATCHEX_DEFAULT_KERNEL_RADIUS;
	GrowthX = PATCHEX_DEFAULT_GROWTH_X;
	GrowthY = PATCHEX_DEFAULT_GROWTH_Y;
}

void UPatchexSettings::PostInitProperties()
{
	Super::PostInitProperties();
	ApplyToConsoleVariables();
}

#if WITH_EDITOR
void UPatchexSettings::PostEditChangeProperty(FPropertyChangedEvent& Event)
{
	Super::PostEditChangeProperty(Event);
	ApplyToConsoleVariables();
}
#endif

void UPatchexSettings::ApplyToConsoleVariables() const
{
	auto Set = [](const TCHAR* Name, const FString& Value)
	{
		if (IConsoleVariable* Variable = IConsoleManager::Get().FindConsoleVariable(Name))
		{
			Variable->Set(*Value, ECVF_SetByProjectSetting);
		}
	};
	Set(TEXT("r.Patchex.Enable"), bEnable ? TEXT("1") : TEXT("0"));
	Set(TEXT("r.Patchex.Preset"), FString::FromInt(Preset));
	Set(TEXT("r.Patchex.Warp"), FString::FromInt(int32(Warp)));
	Set(TEXT("r.Patchex.KernelRadius"), FString::FromInt(KernelRadius));
	Set(TEXT("r.Patchex.GrowthX"), FString::SanitizeFloat(GrowthX));
	Set(TEXT("r.Patchex.GrowthY"), FString::SanitizeFloat(GrowthY));
}
