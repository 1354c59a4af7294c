// The runtime module. It links nothing of patchex at build time: the shared library is loaded
// at start-up from Source/ThirdParty/patchex, where scripts/install.sh puts it (see the README).
using System.IO;
using UnrealBuildTool;

public class Patchex : ModuleRules
{
	public Patchex(ReadOnlyTargetRules Target) : base(Target)
	{
		PCHUsage = PCHUsageMode.UseExplicitOrSharedPCHs;

		PublicDependencyModuleNames.AddRange(new string[] { "Core", "CoreUObject", "Engine", "DeveloperSettings" });
		PrivateDependencyModuleNames.AddRange(new string[]
		{
			"Projects", "RenderCore", "Renderer", "RHI", "VulkanRHI"
		});
		// Renderer internals used by every scene view extension that reads the G-buffers.
		PrivateIncludePaths.Add(Path.Combine(EngineDirectory, "Source/Runtime/Renderer/Private"));
		AddEngineThirdPartyPrivateStaticDependencies(Target, "Vulkan");

		// The installed library: include/patchex.h and lib/libpatchex.so (lib/patchex.dll on Windows).
		string Installed = Path.Combine(PluginDirectory, "Source/ThirdParty/patchex");
		PrivateIncludePaths.Add(Path.Combine(Installed, "include"));
		string Library = Target.Platform == UnrealTargetPlatform.Win64 ? "patchex.dll" : "libpatchex.so";
		RuntimeDependencies.Add(Path.Combine("$(PluginDir)/Source/ThirdParty/patchex/lib", Library));
	}
}
