/* A stand-in for Windows' bcryptprimitives.dll, for the Wine test only (never installed).
 *
 * Rust's std asks ProcessPrng for random bytes (HashMap seeds); every Windows 10 and 11 has
 * it, Wine 8.0 has no bcryptprimitives.dll at all, so ringlab.exe would not start. This one
 * function passes the request to RtlGenRandom (advapi32's SystemFunction036), which Wine has.
 *
 *   x86_64-w64-mingw32-gcc -O2 -shared -o bcryptprimitives.dll bcryptprimitives.c -ladvapi32
 */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG chunk = length > 0x7fffffff ? 0x7fffffff : (ULONG)length;
        if (!SystemFunction036(data, chunk))
            return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE; /* as Windows' own, which never fails */
}
