/* Test shim for wine 8.0 (Debian bookworm), which has no bcryptprimitives.dll.
 *
 * Rust's standard library for Windows (1.78 and later) gets its random bytes from
 * ProcessPrng in bcryptprimitives.dll, a system DLL of Windows 10 and later; the FMUs' DLL and
 * the test importer import it. tests/python/test_platforms.py builds this file with mingw-w64
 * into the wine prefix's system32 only; it never ships in an FMU. ProcessPrng is served by
 * RtlGenRandom (advapi32's SystemFunction036), which wine 8.0 provides. See docs/platforms.md.
 */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG chunk = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk))
            return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
