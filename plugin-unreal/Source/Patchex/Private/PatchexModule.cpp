#include "PatchexApi.h"
#include "PatchexViewExtension.h"

#include "Interfaces/IPluginManager.h"
#include "Misc/CoreDelegates.h"
#include "Misc/Paths.h"
#include "Modules/ModuleManager.h"
#include "SceneViewExtension.h"
#include "ShaderCore.h"

#include <type_traits>

DEFINE_LOG_CATEGORY(LogPatchex);

bool FPatchexApi::Load(const FString& Path)
{
	Handle = FPlatformProcess::GetDllHandle(*Path);
	if (!Handle)
	{
		UE_LOG(LogPatchex, Warning, TEXT("patchex: cannot load %s; frame generation is off"), *Path);
		return false;
	}
	auto Bind = [this](auto& Function, const TCHAR* Name)
	{
		Function = reinterpret_cast<std::remove_reference_t<decltype(Function)>>(FPlatformProcess::GetDllExport(Handle, Name));
		return Function != nullptr;
	};
	bool bComplete = Bind(AbiVersion, TEXT("patchex_abi_version")) && Bind(Create, TEXT("patchex_create")) &&
		Bind(Destroy, TEXT("patchex_destroy")) && Bind(SubmitGBuffers, TEXT("patchex_submit_gbuffers")) &&
		Bind(Extrapolate, TEXT("patchex_extrapolate")) && Bind(GetFrameStats, TEXT("patchex_get_frame_stats")) &&
		Bind(LastError, TEXT("patchex_last_error"));
	if (!bComplete || AbiVersion() != PATCHEX_ABI_VERSION)
	{
		UE_LOG(LogPatchex, Warning, TEXT("patchex: %s is not the library of this plugin's header (ABI %u expected)"),
			*Path, PATCHEX_ABI_VERSION);
		Unload();
		return false;
	}
	return true;
}

void FPatchexApi::Unload()
{
	if (Handle)
	{
		FPlatformProcess::FreeDllHandle(Handle);
	}
	*this = FPatchexApi();
}

class FPatchexModule final : public IModuleInterface
{
public:
	virtual void StartupModule() override
	{
		const FString PluginDir = IPluginManager::Get().FindPlugin(TEXT("Patchex"))->GetBaseDir();
		AddShaderSourceDirectoryMapping(TEXT("/Plugin/Patchex"), FPaths::Combine(PluginDir, TEXT("Shaders")));
#if PLATFORM_WINDOWS
		const TCHAR* Library = TEXT("patchex.dll");
#else
		const TCHAR* Library = TEXT("libpatchex.so");
#endif
		if (Api.Load(FPaths::Combine(PluginDir, TEXT("Source/ThirdParty/patchex/lib"), Library)))
		{
			// The extension checks for the Vulkan RHI itself: the RHI is not up yet at PostConfigInit.
			FCoreDelegates::OnPostEngineInit.AddLambda([this]
			{
				Extension = FSceneViewExtensions::NewExtension<FPatchexViewExtension>(Api);
			});
		}
	}

	virtual void ShutdownModule() override
	{
		Extension.Reset();  // destroys the context on the render thread, after the GPU is idle
		Api.Unload();
	}

private:
	FPatchexApi Api;
	TSharedPtr<FPatchexViewExtension, ESPMode::ThreadSafe> Extension;
};

IMPLEMENT_MODULE(FPatchexModule, Patchex)
