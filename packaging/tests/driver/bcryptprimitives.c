/* Test-only stand-in for Windows 10's bcryptprimitives.dll, which wine 8 lacks: Rust's std
 * (x86_64-pc-windows-gnu) imports ProcessPrng from it for its hash-map keys. Built with mingw
 * and placed beside the driver executable by packaging/tests/platforms.rs. */
#include <windows.h>
typedef BOOLEAN(WINAPI *gen_random_t)(PVOID, ULONG);
__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len) {
    static gen_random_t gen = NULL;
    if (!gen) gen = (gen_random_t)(void *)GetProcAddress(LoadLibraryA("advapi32.dll"), "SystemFunction036");
    while (len > 0) {
        ULONG chunk = len > 0x10000000 ? 0x10000000 : (ULONG)len;
        if (!gen || !gen(data, chunk)) return FALSE;
        data += chunk;
        len -= chunk;
    }
    return TRUE;
}
