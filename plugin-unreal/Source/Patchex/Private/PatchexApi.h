// patchex's C entry points, loaded from the shared library at start-up: the plugin links nothing
// at build time, so a project without the library (or on another RHI) still loads.
#pragma once

#include "CoreMinimal.h"
#include "patchex.h"

struct FPatchexApi
{
	decltype(&patchex_abi_version) AbiVersion = nullptr;
	decltype(&patchex_create) Create = nullptr;
	decltype(&patchex_destroy) Destroy = nullptr;
	decltype(&patchex_submit_gbuffers) SubmitGBuffers = nullptr;
	decltype(&patchex_extrapolate) Extrapolate = nullptr;
	decltype(&patchex_get_frame_stats) GetFrameStats = nullptr;
	decltype(&patchex_last_error) LastError = nullptr;

	/** Loads the library at `Path`; false, with the reason logged, if it cannot be used. */
	bool Load(const FString& Path);
	void Unload();

private:
	void* Handle = nullptr;
};
